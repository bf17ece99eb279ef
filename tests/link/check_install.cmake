# Installs BUILD_DIR into WORK_DIR/prefix, then builds the consumer against it
# with find_package(geom) and with pkg-config, and runs both programs.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGV}\n${out}\n${err}")
  endif()
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
run(${CMAKE_COMMAND} -S ${SRC_DIR} -B ${WORK_DIR}/cmake-build -DCMAKE_C_COMPILER=${C_COMPILER}
    -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/cmake-build)
run(${WORK_DIR}/cmake-build/consumer_cmake)
file(GLOB pcdir ${prefix}/lib*/pkgconfig ${prefix}/lib/*/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "${pcdir}")
execute_process(COMMAND pkg-config --cflags --libs --static geom OUTPUT_VARIABLE flags
  RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config does not find geom.pc in ${pcdir}")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
# pkg-config gives -L<libdir> -lgeom, which links the shared library.
run(${C_COMPILER} ${SRC_DIR}/main.c -o ${WORK_DIR}/consumer_pkgconfig ${flags})
execute_process(COMMAND pkg-config --variable=libdir geom OUTPUT_VARIABLE libdir
  OUTPUT_STRIP_TRAILING_WHITESPACE)
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${libdir} ${WORK_DIR}/consumer_pkgconfig)

# A C++-only project (no C enabled): find_package(geom) with the static
# library's OpenMP runtime, and the shared library.
run(${CMAKE_COMMAND} -S ${SRC_DIR}/../consumer_cxx -B ${WORK_DIR}/cxx-build
    -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/cxx-build)
run(${WORK_DIR}/cxx-build/consumer_cxx)
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${libdir} ${WORK_DIR}/cxx-build/consumer_cxx_shared)

# The Python package installed with the library: it finds the installed
# libgeom through _libpath.py (GEOM_LIBRARY unset; PYTHONPATH names the
# scratch prefix's site directory only because it is not a system prefix).
if(PYTHON AND EXISTS ${PYTHON})
  file(GLOB_RECURSE _init ${prefix}/__init__.py)
  list(FILTER _init INCLUDE REGEX "/geom/__init__\\.py$")
  if(NOT _init)
    message(FATAL_ERROR "cmake --install put no Python package geom under ${prefix}")
  endif()
  list(GET _init 0 _init)
  get_filename_component(_site ${_init} DIRECTORY)
  get_filename_component(_site ${_site} DIRECTORY)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=GEOM_LIBRARY PYTHONPATH=${_site}
      ${PYTHON} -c "import geom; p = geom._ffi.library_path; assert p.startswith('${prefix}'), p; print(p)"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "installed Python package does not load the installed library:\n${out}\n${err}")
  endif()
endif()
