# Tests of the curve and surface tools (geom-tessellate, geom-curve): one
# shell script each, run with the built tool, the data directory and
# Debian's python3 (GEOM_SYSTEM_PYTHON3) for the reference answers.
# Included from tests/tools/CMakeLists.txt after GEOM_BASH and
# GEOM_SYSTEM_PYTHON3 are set; a tool that was not built has no test. The
# JSON parts need cJSON at build time (geom_surface_json): without it the
# scripts check that JSON input is refused and test the rest.
foreach(_verb tessellate curve)
  if(TARGET geom-${_verb})
    set(_json 0)
    if(TARGET geom_surface_json)
      set(_json 1)
    endif()
    add_test(NAME tool_geom_${_verb}
      COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_${_verb}.sh
              $<TARGET_FILE:geom-${_verb}> ${PROJECT_SOURCE_DIR}/data ${_json})
    set_tests_properties(tool_geom_${_verb} PROPERTIES
      ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
  endif()
endforeach()
