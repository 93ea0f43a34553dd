# OslLLVM: how the project's targets link LLVM and MLIR.
#
# Everything links the one shared libMLIR.so and libLLVM.so (small
# binaries, fast relinks, one copy of LLVM's static registries), except a
# target whose OSL_STATIC_LLVM property is set (osl-run): it links LLVM's
# and MLIR's static archives, of which the linker takes only the members it
# needs. A process that compiles one shader pays most of its compile in
# first-touch costs - the dynamic loader's relocations and symbol lookups
# over libLLVM's and libMLIR's exported symbols, lazy binding, page faults
# - and statically linked, osl-run starts in half the time and compiles
# marble from source in 0.75x (bench/RESULTS.md, session nineteen).

option(OSL_MLIR_STATIC_LLVM "Link osl-run with LLVM's and MLIR's static archives" ON)

add_library(OslLLVM INTERFACE)
if(OSL_MLIR_STATIC_LLVM)
  file(GLOB OSL_LLVM_ARCHIVES "${LLVM_LIBRARY_DIR}/libMLIR*.a" "${LLVM_LIBRARY_DIR}/libLLVM*.a")
  # Bindings and generators: nothing the compiler calls.
  list(FILTER OSL_LLVM_ARCHIVES EXCLUDE REGEX "CAPI|Python|TableGen|Tblgen|Lsp|MlirOptMain")
  set(osl_static "$<BOOL:$<TARGET_PROPERTY:OSL_STATIC_LLVM>>")
  target_link_libraries(OslLLVM INTERFACE
    "$<${osl_static}:-Wl,--start-group;${OSL_LLVM_ARCHIVES};-Wl,--end-group;z;zstd;rt;dl;m>"
    "$<$<NOT:${osl_static}>:MLIR;LLVM>")
else()
  target_link_libraries(OslLLVM INTERFACE MLIR LLVM)
endif()
set(OSL_MLIR_LIBS OslLLVM)

# add_mlir_library links each library to the imported `LLVM` (libLLVM.so)
# and add_llvm_executable each executable, themselves;
# osl_link_llvm_through_oslllvm(dir) makes the targets under `dir` reach
# LLVM through OslLLVM instead, so that a static target gets no second,
# shared copy of LLVM.
function(osl_link_llvm_through_oslllvm dir)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  list(REMOVE_ITEM targets OslLLVM)
  foreach(target IN LISTS targets)
    foreach(property LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
      get_target_property(links ${target} ${property})
      if(links)
        list(TRANSFORM links REPLACE "^LLVM$" "OslLLVM")
        list(TRANSFORM links REPLACE "^\\$<LINK_ONLY:LLVM>$" "$<LINK_ONLY:OslLLVM>")
        set_target_properties(${target} PROPERTIES ${property} "${links}")
      endif()
    endforeach()
  endforeach()
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(subdir IN LISTS subdirs)
    osl_link_llvm_through_oslllvm(${subdir})
  endforeach()
endfunction()
