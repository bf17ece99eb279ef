# Test of geom-subdivide: a shell script run with the built tool and
# Debian's python3 (GEOM_SYSTEM_PYTHON3) for the checks. Included from
# tests/tools/CMakeLists.txt; no test when the tool was not built.
if(TARGET geom-subdivide)
  add_test(NAME tool_geom_subdivide
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_subdivide.sh
            $<TARGET_FILE:geom-subdivide>)
  set_tests_properties(tool_geom_subdivide PROPERTIES
    ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
