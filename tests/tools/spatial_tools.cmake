# Tests of geom-query (spatial indices). Included by tests/tools/CMakeLists.txt,
# which defines GEOM_BASH and GEOM_SYSTEM_PYTHON3.
if(TARGET geom-query)
  add_test(NAME tool_geom_query
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_query.sh $<TARGET_FILE:geom-query>)
  set_tests_properties(tool_geom_query PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
