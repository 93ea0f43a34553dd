# Installs headers, libraries, tools and a CMake package, so a renderer can
#   find_package(OslMlir CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE OslMlir::OslMlir)
# and embed the compiler and runtime (see examples/embed).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(DIRECTORY ${PROJECT_BINARY_DIR}/include/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.inc")

# add_mlir_library installs its own targets; these are plain CMake ones.
install(TARGETS OslRuntime OslImageIO OslClosures OslStrings OslReference
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS OslOiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
# OpenImageIO's plugin and the Python query module, each finding
# ../bin/osl-run from where it is installed.
if(TARGET osl-imageio)
  install(TARGETS osl-imageio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
endif()
install(FILES ${PROJECT_SOURCE_DIR}/python/oslquery.py DESTINATION ${CMAKE_INSTALL_LIBDIR}/python)
foreach(tool osl-opt osl-run osl-assemble osl-imgdiff)
  if(TARGET ${tool})
    install(TARGETS ${tool} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()

install(PROGRAMS ${PROJECT_SOURCE_DIR}/tools/osl-farm/osl-farm
  DESTINATION ${CMAKE_INSTALL_BINDIR})

configure_package_config_file(
  ${PROJECT_SOURCE_DIR}/cmake/OslMlirConfig.cmake.in
  ${PROJECT_BINARY_DIR}/OslMlirConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/OslMlir)
write_basic_package_version_file(
  ${PROJECT_BINARY_DIR}/OslMlirConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/OslMlirConfig.cmake
              ${PROJECT_BINARY_DIR}/OslMlirConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/OslMlir)
