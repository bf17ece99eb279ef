# SISL part of the validation shim (validate_sisl.cpp, declared in
# geom_validate_sisl.h): reference B-spline and NURBS curve and surface
# evaluation from SINTEF's SISL (Debian libsisl-dev) for the curve and
# surface tests and benchmarks. Included from tests/validate/CMakeLists.txt.
#
# Debian ships only a static, non-PIC libsisl.a (no CMake or pkg-config
# files): it is found directly and linked into test and benchmark programs
# only, never into libgeom.
find_library(GEOM_SISL_LIBRARY NAMES sisl)
find_path(GEOM_SISL_INCLUDE_DIR sisl.h)
if(GEOM_SISL_LIBRARY AND GEOM_SISL_INCLUDE_DIR)
  message(STATUS "geom_validate: SISL found (${GEOM_SISL_LIBRARY}), building the SISL part")
  add_library(geom_validate_sisl_lib INTERFACE)
  target_include_directories(geom_validate_sisl_lib INTERFACE ${GEOM_SISL_INCLUDE_DIR})
  find_library(GEOM_SISL_LIBM m)
  target_link_libraries(geom_validate_sisl_lib INTERFACE ${GEOM_SISL_LIBRARY}
    $<$<BOOL:${GEOM_SISL_LIBM}>:${GEOM_SISL_LIBM}>)
  geom_validate_part(sisl SOURCES validate_sisl.cpp LIBS geom_validate_sisl_lib)
  geom_validate_test(test_validate_sisl.c MODULES curve surface)
  geom_validate_test(test_validate_ray_sisl.c MODULES ray)
  # With the CGAL part too, the test also checks the teapot's watertight
  # body (and the sphere and torus) with CGAL's gv_soup_check.
  if("cgal" IN_LIST GEOM_VALIDATE_BUILT_PARTS)
    set_source_files_properties(test_validate_sisl.c PROPERTIES COMPILE_DEFINITIONS GV_HAVE_CGAL=1)
  endif()
else()
  message(STATUS "geom_validate: SISL not found (install libsisl-dev), SISL part and its tests skipped")
endif()
