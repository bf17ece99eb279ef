# Validation of the STEP reader and tessellation (geom-tessellate IN.step)
# against gmsh/OpenCASCADE (Debian's gmsh, gmsh-doc and python3-gmsh, which
# .ci/deps installs): every STEP file gmsh-doc ships plus data/sphere.step.
# The script skips with a message when gmsh's Python module is missing.
if(TARGET geom-tessellate AND TARGET geom-info)
  add_test(NAME tool_geom_tessellate_step
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_tessellate_step.sh
            $<TARGET_FILE:geom-tessellate> $<TARGET_FILE:geom-info> ${PROJECT_SOURCE_DIR}/data)
  set_tests_properties(tool_geom_tessellate_step PROPERTIES
    ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}" SKIP_RETURN_CODE 77 TIMEOUT 1200)
endif()

# The output estimate before the work and the limits (issue 15).
if(TARGET geom-tessellate)
  add_test(NAME tool_step_limits
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_step_limits.sh
            $<TARGET_FILE:geom-tessellate> ${PROJECT_SOURCE_DIR}/data)
  set_tests_properties(tool_step_limits PROPERTIES
    ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}" TIMEOUT 600)
endif()
