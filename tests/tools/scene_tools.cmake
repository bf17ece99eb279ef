# Tests of geom-render (and geom-scene when built): shell scripts run with the
# built tools and Debian's python3 for the checks (PFM read by hand).
if(TARGET geom-render)
  add_test(NAME tool_geom_render
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_render.sh
            $<TARGET_FILE:geom-render> ${PROJECT_SOURCE_DIR}/data)
  set_tests_properties(tool_geom_render PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
if(TARGET geom-scene)
  add_test(NAME tool_geom_scene
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_scene.sh
            $<TARGET_FILE:geom-scene> ${PROJECT_SOURCE_DIR}/data)
  set_tests_properties(tool_geom_scene PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
