# Tests of the mesh-attribute tools (geom-normals, geom-tangents,
# geom-features, geom-clip): one shell script each, run with the built tool
# and Debian's python3 (GEOM_SYSTEM_PYTHON3) for the reference answers.
# Included from tests/tools/CMakeLists.txt after GEOM_BASH and
# GEOM_SYSTEM_PYTHON3 are set; a tool that was not built (its modules are
# disabled) has no test.
foreach(_verb normals tangents features clip)
  if(TARGET geom-${_verb})
    add_test(NAME tool_geom_${_verb}
      COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_${_verb}.sh
              $<TARGET_FILE:geom-${_verb}>)
    set_tests_properties(tool_geom_${_verb} PROPERTIES
      ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
  endif()
endforeach()
