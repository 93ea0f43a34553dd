# Installs the build into a scratch prefix, then configures, builds and runs
# examples/embed against it with find_package(OslMlir): proves the CMake
# package works for a project outside this tree.
set(prefix "${BUILD_DIR}/package-test/prefix")
set(embed "${BUILD_DIR}/package-test/embed")
file(REMOVE_RECURSE "${BUILD_DIR}/package-test")
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed: ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/embed" -B "${embed}" -G Ninja
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build "${embed}")
run("${embed}/embed")
