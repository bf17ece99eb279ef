# Tests of the meshio tools (geom-info, geom-convert). Included by
# tests/tools/CMakeLists.txt, which defines GEOM_BASH and GEOM_SYSTEM_PYTHON3:
#     include(${CMAKE_CURRENT_SOURCE_DIR}/meshio_tools.cmake)

if(TARGET geom-info)
  add_test(NAME tool_geom_info
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_info.sh
            $<TARGET_FILE:geom-info> ${PROJECT_SOURCE_DIR}/data)
  set_tests_properties(tool_geom_info PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()

if(TARGET geom-convert AND TARGET geom-info)
  add_test(NAME tool_geom_convert
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_geom_convert.sh
            $<TARGET_FILE:geom-convert> $<TARGET_FILE:geom-info> ${PROJECT_SOURCE_DIR}/data)
  set_tests_properties(tool_geom_convert PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()

# The .glb round trip of a Z-up mesh with --up z on writing and reading.
if(TARGET geom-convert AND TARGET geom-info AND TARGET geom-normals)
  add_test(NAME tool_glb_up
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_glb_up.sh
            $<TARGET_FILE:geom-convert> $<TARGET_FILE:geom-info> $<TARGET_FILE:geom-normals>)
  set_tests_properties(tool_glb_up PROPERTIES ENVIRONMENT "PYTHON3=${GEOM_SYSTEM_PYTHON3}")
endif()
