# Tool tests of the ray module (included by tests/tools/CMakeLists.txt).
if(TARGET geom-raycast)
  add_test(NAME tool_geom_raycast
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_SOURCE_DIR}/test_geom_raycast.sh
            $<TARGET_FILE:geom-raycast> ${PROJECT_VERSION})
  set_tests_properties(tool_geom_raycast PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
# Volumes in scene files: every format and encoding geom-iso --volume reads.
if(TARGET geom-raycast AND TARGET geom_scene_json)
  add_test(NAME tool_scene_volumes
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_SOURCE_DIR}/test_scene_volumes.sh $<TARGET_FILE:geom-raycast>
            $<$<AND:$<TARGET_EXISTS:geom-scene>,$<TARGET_EXISTS:geom-iso>>:$<TARGET_FILE:geom-scene>>
            $<$<AND:$<TARGET_EXISTS:geom-scene>,$<TARGET_EXISTS:geom-iso>>:$<TARGET_FILE:geom-iso>>)
  set_tests_properties(tool_scene_volumes PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
