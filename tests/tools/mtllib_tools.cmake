# --mtllib on the tools that write OBJ through cli_mesh (issue 14): one
# script over every such tool that was built.
set(_mtl_tools "")
foreach(_verb normals tangents clip subdivide tessellate convert features)
  if(TARGET geom-${_verb})
    list(APPEND _mtl_tools $<TARGET_FILE:geom-${_verb}>)
  endif()
endforeach()
if(_mtl_tools)
  add_test(NAME tool_mtllib_option
    COMMAND ${GEOM_BASH} ${CMAKE_CURRENT_LIST_DIR}/test_mtllib_option.sh
            ${PROJECT_SOURCE_DIR}/data ${_mtl_tools})
endif()
