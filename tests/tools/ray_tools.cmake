# Tool tests of the ray module (included by tests/tools/CMakeLists.txt).
if(TARGET geom-raycast)
  add_test(NAME tool_geom_raycast
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_SOURCE_DIR}/test_geom_raycast.sh
            $<TARGET_FILE:geom-raycast> ${PROJECT_VERSION})
  set_tests_properties(tool_geom_raycast PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
