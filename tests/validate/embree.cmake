# Embree part of the validation shim (validate_embree.cpp, declared in
# geom_validate_embree.h): reference ray/triangle-mesh answers from Intel's
# Embree 3 (Debian libembree-dev), in its default and robust (watertight)
# modes, on one thread. Included from tests/validate/CMakeLists.txt.
find_package(embree 3 QUIET)
if(embree_FOUND)
  message(STATUS "geom_validate: Embree ${embree_VERSION} found, building the Embree part")
  geom_validate_part(embree SOURCES validate_embree.cpp LIBS embree)
  geom_validate_test(test_validate_ray_embree.c MODULES ray)
else()
  message(STATUS "geom_validate: Embree not found (install libembree-dev), Embree part and its tests skipped")
endif()
