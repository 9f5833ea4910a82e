# Installs the library as a CMake package: find_package(rvor) then target_link_libraries(app rvor::rvor).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(RVOR_EXPORTED_TARGETS rvor rvor_core rvor_fields rvor_medit rvor_mesh_check rvor_canvas rvor_solver rvor_io
    rvor_opencl rvor_dual rvor_kernels)
install(TARGETS ${RVOR_EXPORTED_TARGETS} EXPORT rvorTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY host/include/rvor DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT rvorTargets NAMESPACE rvor:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rvor)
configure_package_config_file(cmake/rvorConfig.cmake.in
  "${CMAKE_CURRENT_BINARY_DIR}/rvorConfig.cmake"
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rvor)
write_basic_package_version_file("${CMAKE_CURRENT_BINARY_DIR}/rvorConfigVersion.cmake"
  COMPATIBILITY SameMajorVersion)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/rvorConfig.cmake"
              "${CMAKE_CURRENT_BINARY_DIR}/rvorConfigVersion.cmake"
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rvor)
