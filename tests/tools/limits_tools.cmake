# Output limits (--max-triangles, --max-memory) of geom-tessellate and
# geom-iso, with their estimates checked against the counts made.
if(TARGET geom-tessellate AND TARGET geom-iso)
  add_test(NAME tool_limits
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_limits.sh
            $<TARGET_FILE:geom-tessellate> $<TARGET_FILE:geom-iso> ${PROJECT_SOURCE_DIR}/data/teapot.bpt)
  set_tests_properties(tool_limits PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
if(TARGET geom-info AND TARGET geom-iso AND TARGET geom-convert)
  add_test(NAME tool_feedback
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_feedback.sh
            $<TARGET_FILE:geom-info> $<TARGET_FILE:geom-iso> $<TARGET_FILE:geom-convert>
            ${PROJECT_SOURCE_DIR}/data/cube_seams.obj)
  set_tests_properties(tool_feedback PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
get_property(_help_tools GLOBAL PROPERTY GEOM_TOOLS)
if(_help_tools)
  set(_help_paths "")
  foreach(_t IN LISTS _help_tools)
    list(APPEND _help_paths $<TARGET_FILE:${_t}>)
  endforeach()
  add_test(NAME tool_help_examples
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_tools_help.sh ${PROJECT_SOURCE_DIR}
            ${_help_paths})
endif()
