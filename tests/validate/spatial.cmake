# Spatial part of the validation shim (validate_spatial.cpp, declared in
# geom_validate_spatial.h): closest points from CGAL's AABB_tree for the
# spatial tests. Included from tests/validate/CMakeLists.txt.
find_package(CGAL QUIET)
if(CGAL_FOUND)
  geom_validate_part(cgal_spatial SOURCES validate_spatial.cpp LIBS CGAL::CGAL)
  geom_validate_test(test_validate_spatial.c MODULES spatial meshio)
endif()
