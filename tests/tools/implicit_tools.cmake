# Tool tests of the implicit module (included by tests/tools/CMakeLists.txt).
if(TARGET geom-contour)
  add_test(NAME tool_geom_contour
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_SOURCE_DIR}/test_geom_contour.sh
            $<TARGET_FILE:geom-contour> ${PROJECT_VERSION})
  set_tests_properties(tool_geom_contour PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
