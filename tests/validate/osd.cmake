# OpenSubdiv part of the validation shim (validate_osd.cpp, declared in
# geom_validate_osd.h): reference subdivision from OpenSubdiv 3's Far for the
# subdiv tests and benchmark. Included from tests/validate/CMakeLists.txt.
#
# find_package(OpenSubdiv) is not used: Debian's libosd-dev ships a CMake
# configuration that names static libraries it does not install. The CPU
# library and the headers are found directly.
find_library(GEOM_OSD_CPU_LIBRARY NAMES osdCPU)
find_path(GEOM_OSD_INCLUDE_DIR opensubdiv/far/topologyRefiner.h)
if(GEOM_OSD_CPU_LIBRARY AND GEOM_OSD_INCLUDE_DIR)
  message(STATUS "geom_validate: OpenSubdiv found (${GEOM_OSD_CPU_LIBRARY}), building the OpenSubdiv part")
  add_library(geom_validate_osd_lib INTERFACE)
  target_include_directories(geom_validate_osd_lib INTERFACE ${GEOM_OSD_INCLUDE_DIR})
  target_link_libraries(geom_validate_osd_lib INTERFACE ${GEOM_OSD_CPU_LIBRARY})
  geom_validate_part(osd SOURCES validate_osd.cpp LIBS geom_validate_osd_lib)
  geom_validate_test(test_validate_subdiv.c MODULES subdiv meshio)
else()
  message(STATUS "geom_validate: OpenSubdiv not found (install libosd-dev), OpenSubdiv part and its tests skipped")
endif()
