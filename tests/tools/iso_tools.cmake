# Tests of geom-iso (marching cubes of expressions and volumes). Included by
# tests/tools/CMakeLists.txt, which defines GEOM_BASH and GEOM_SYSTEM_PYTHON3;
# no test when the tool was not built (iso, implicit or meshio disabled).
if(TARGET geom-iso)
  add_test(NAME tool_geom_iso
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_iso.sh $<TARGET_FILE:geom-iso>)
  set_tests_properties(tool_geom_iso PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
if(TARGET geom-iso)
  add_test(NAME tool_geom_iso_volumes
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_iso_volumes.sh $<TARGET_FILE:geom-iso>)
  set_tests_properties(tool_geom_iso_volumes PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
