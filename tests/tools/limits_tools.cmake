# Output limits (--max-triangles, --max-memory) of geom-tessellate and
# geom-iso, with their estimates checked against the counts made.
if(TARGET geom-tessellate AND TARGET geom-iso)
  add_test(NAME tool_limits
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_limits.sh
            $<TARGET_FILE:geom-tessellate> $<TARGET_FILE:geom-iso> ${PROJECT_SOURCE_DIR}/data/teapot.bpt)
  set_tests_properties(tool_limits PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
if(TARGET geom-info AND TARGET geom-iso)
  add_test(NAME tool_feedback
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_feedback.sh
            $<TARGET_FILE:geom-info> $<TARGET_FILE:geom-iso>)
  set_tests_properties(tool_feedback PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
