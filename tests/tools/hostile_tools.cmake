# Hostile-use tests of the tools (issue 15): what -o does to every kind of
# destination, and the hostile-input corpus tests/data/hostile through every
# tool. Included by tests/tools/CMakeLists.txt.

if(TARGET geom-bary AND TARGET geom-convert)
  add_test(NAME tool_output_safety
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_output_safety.sh
            $<TARGET_FILE:geom-bary> $<TARGET_FILE:geom-convert> ${PROJECT_SOURCE_DIR}/data)
endif()

if(TARGET geom-tessellate AND TARGET geom-curve AND GEOM_CJSON_LIBRARY)
  add_test(NAME tool_extremes
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_extremes.sh
            $<TARGET_FILE:geom-tessellate> $<TARGET_FILE:geom-curve> ${PROJECT_SOURCE_DIR}/data
            $<$<TARGET_EXISTS:geom-contour>:$<TARGET_FILE:geom-contour>>)
  set_tests_properties(tool_extremes PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()

# The hostile-input corpus through every tool that reads it.
set(_hostile_tools "")
foreach(_t geom-info geom-convert geom-normals geom-tangents geom-features geom-subdivide
           geom-tessellate geom-iso geom-render geom-scene geom-raycast geom-query)
  if(TARGET ${_t})
    list(APPEND _hostile_tools $<TARGET_FILE:${_t}>)
  endif()
endforeach()
if(_hostile_tools)
  add_test(NAME tool_hostile_corpus
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_hostile_corpus.sh
            ${PROJECT_SOURCE_DIR}/tests/data/hostile ${_hostile_tools})
endif()

# Every tool's error paths (bad option values, bad inputs): no "invalid
# argument: ok", no empty message, no hint naming a library field (issue 15).
if(TARGET geom-info)
  add_test(NAME tool_messages
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_messages.sh ${PROJECT_SOURCE_DIR}/data
            $<TARGET_FILE_DIR:geom-info>)
  set_tests_properties(tool_messages PROPERTIES TIMEOUT 900)
endif()
