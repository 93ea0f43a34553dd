# The prebuilt library: noise_catalog.osl compiled by osl-run at every
# batch width, its library functions' objects kept in OUT_DIR/library,
# where osl-run looks before compiling one (LibraryObjects.h). Kernels the
# runs leave beside them are removed. Run by the build (cmake -P) with
#   OSL_RUN  the osl-run just built
#   CATALOG  noise_catalog.osl
#   OUT_DIR  <build>/share/osl-mlir
#   STAMP    the file that marks the library built
file(REMOVE_RECURSE "${OUT_DIR}/library")
foreach(width 1 4 8 16)
  execute_process(
    COMMAND "${OSL_RUN}" "${CATALOG}" --width ${width} -g 1 1 -t 1 --cache-dir "${OUT_DIR}"
    RESULT_VARIABLE status
    OUTPUT_QUIET
    ERROR_VARIABLE errors)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "the prebuilt library at width ${width}: ${errors}")
  endif()
endforeach()
file(GLOB kernels "${OUT_DIR}/*.oslk")
if(kernels)
  file(REMOVE ${kernels})
endif()
file(TOUCH "${STAMP}")
