# Every third-party dependency comes from a Debian package (see setup.sh); this file is the one
# place that finds them and papers over their known packaging traps.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(OpenMP REQUIRED COMPONENTS CXX)
find_package(glm REQUIRED)
find_package(nlohmann_json 3.11 REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(ZLIB REQUIRED)
# The volume readers beyond NRRD and MetaImage (renderers/volume/): NIfTI-1/-2 through
# nifticlib's nifti2 library, TIFF stacks through libtiff, DICOM series through GDCM.
# Debian 12's NIFTIConfig.cmake points at /usr/lib/libznz.so.3.0.0, which the package installs
# under the multiarch folder instead, so the library is found directly.
find_path(NIFTI_INCLUDE_DIR nifti/nifti2_io.h REQUIRED)
find_library(NIFTI2_LIBRARY nifti2 REQUIRED)
find_library(NIFTI_ZNZ_LIBRARY znz REQUIRED)
add_library(svr_nifti INTERFACE IMPORTED GLOBAL)
set_target_properties(svr_nifti PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES "${NIFTI_INCLUDE_DIR};${NIFTI_INCLUDE_DIR}/nifti"
  INTERFACE_LINK_LIBRARIES "${NIFTI2_LIBRARY};${NIFTI_ZNZ_LIBRARY};ZLIB::ZLIB;m")
find_package(TIFF REQUIRED)
find_package(GDCM CONFIG REQUIRED)

# Debian 12's OpenImageIO config lists a non-existent opencv4 include directory on its imported
# target; CMake then refuses to build anything that links it. Filter that entry out.
find_package(OpenImageIO CONFIG REQUIRED)
foreach(_oiio_target OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
  if(TARGET ${_oiio_target})
    get_target_property(_dirs ${_oiio_target} INTERFACE_INCLUDE_DIRECTORIES)
    if(_dirs)
      list(FILTER _dirs EXCLUDE REGEX "opencv4")
      set_target_properties(${_oiio_target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_dirs}")
    endif()
  endif()
endforeach()

# OSMesa ships no CMake config; use pkg-config. Never link libGL/libOpenGL beside it: GL calls
# would then resolve to the wrong library and silently do nothing.
find_package(PkgConfig REQUIRED)
pkg_check_modules(OSMESA IMPORTED_TARGET osmesa)
if(OSMESA_FOUND)
  message(STATUS "svr: OSMesa ${OSMESA_VERSION} found, the gl backend will be built")
else()
  message(STATUS "svr: OSMesa not found (install libosmesa6-dev), the gl backend is left out")
endif()
# EGL (libglvnd's libEGL, with Mesa's vendor library libegl-mesa0 behind it): the gl backend's
# second platform, headless on a GPU or Mesa's software device.
pkg_check_modules(EGL IMPORTED_TARGET egl)
if(EGL_FOUND)
  message(STATUS "svr: EGL ${EGL_VERSION} found, the gl backend gets its EGL platform")
else()
  message(STATUS "svr: EGL not found (install libegl-dev), the gl backend has OSMesa only")
endif()

# SHA-256: the disk cache's keys and checksums (spectral/disk_cache), and in the tests the
# volume payloads against the checksums in data/volumes/*.nhdr.
find_package(OpenSSL REQUIRED COMPONENTS Crypto)
if(SVR_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(SVR_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()

# cpp-httplib (Debian's compiled libcpp-httplib): the HTTP server of `svr view`. Without it svr
# builds all the same, and `svr view` says what to install.
pkg_check_modules(HTTPLIB IMPORTED_TARGET cpp-httplib)
if(HTTPLIB_FOUND)
  message(STATUS "svr: cpp-httplib ${HTTPLIB_VERSION} found, `svr view` will be built")
else()
  message(STATUS "svr: cpp-httplib not found (install libcpp-httplib-dev), `svr view` is left out")
endif()
