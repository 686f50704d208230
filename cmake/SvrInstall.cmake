# What `cmake --install` puts where (issue 50), and the packages made from it:
#   bin/svr, bin/svr-mpi            the command line (svr-mpi where MPI was found)
#   lib/…/libsvr.so.0.1             the public API (api/), SONAME libsvr.so.0.1
#   include/svr/                    its headers (include/svr/svr.h first)
#   lib/…/cmake/svr/                find_package(svr CONFIG): the target svr::svr
#   lib/…/pkgconfig/svr.pc          pkg-config --cflags --libs svr
#   share/svr/                      spectra, scenes, palettes, volumes; scripts/ for the charts
#   share/doc/svr/                  README.md and docs/
# An installed svr finds share/svr relative to itself (base/data_dir.h).

include(CMakePackageConfigHelpers)

install(TARGETS svr RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET svr-mpi)
  install(TARGETS svr-mpi RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
install(TARGETS libsvr EXPORT svrTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Unspecified)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/svr DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT svrTargets NAMESPACE svr:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/svr)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/svrConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/svrConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/svr)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/svrConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/svrConfig.cmake ${CMAKE_BINARY_DIR}/svrConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/svr)
file(RELATIVE_PATH SVR_PC_TO_PREFIX /root/${CMAKE_INSTALL_LIBDIR}/pkgconfig /root)
configure_file(${PROJECT_SOURCE_DIR}/cmake/svr.pc.in ${CMAKE_BINARY_DIR}/svr.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/svr.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/svr)
install(FILES ${PROJECT_SOURCE_DIR}/harness/report.py ${PROJECT_SOURCE_DIR}/harness/plot_spectra.py
        DESTINATION ${CMAKE_INSTALL_DATADIR}/svr/scripts)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})

# cpack -G DEB (run in the build folder): svr_VERSION_amd64.deb, its shared-library
# dependencies found by dpkg-shlibdeps, and the interpreter the chart scripts need.
set(CPACK_PACKAGE_NAME svr)
set(CPACK_PACKAGE_VENDOR "svr")
set(CPACK_PACKAGE_CONTACT "svr developers <svr@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "spectral volume rendering with post-illumination")
set(CPACK_PACKAGE_INSTALL_DIRECTORY svr)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3-matplotlib, python3-numpy")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "chromium")
include(CPack)
