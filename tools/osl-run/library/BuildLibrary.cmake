# The prebuilt library: noise_catalog.osl compiled by osl-run at every
# batch width, its library functions' objects kept in OUT_DIR/library,
# where osl-run looks before compiling one (LibraryObjects.h). The runs
# compile into a scratch cache of their own (no kernel an earlier run left
# can stand in for a compile), whose library/ then replaces OUT_DIR's. The
# library only saves compile time: if osl-run cannot make it (a host that
# cannot JIT, a sanitizer's exit status), the build warns and goes on
# without it. Run by the build (cmake -P) with
#   OSL_RUN  the osl-run just built
#   CATALOG  noise_catalog.osl
#   OUT_DIR  <build>/share/osl-mlir
#   STAMP    the file that marks the library built
set(scratch "${OUT_DIR}/library-build")
file(REMOVE_RECURSE "${OUT_DIR}/library" "${scratch}")
foreach(width 1 4 8 16)
  execute_process(
    COMMAND "${OSL_RUN}" "${CATALOG}" --width ${width} -g 1 1 -t 1 --cache-dir "${scratch}"
            --outline-every-routine
    RESULT_VARIABLE status
    OUTPUT_QUIET
    ERROR_VARIABLE errors)
  if(NOT status EQUAL 0)
    message(WARNING "no prebuilt noise library (osl-run failed at width ${width}): ${errors}")
    file(REMOVE_RECURSE "${scratch}")
    file(TOUCH "${STAMP}")
    return()
  endif()
endforeach()
file(RENAME "${scratch}/library" "${OUT_DIR}/library")
file(REMOVE_RECURSE "${scratch}")
file(TOUCH "${STAMP}")
