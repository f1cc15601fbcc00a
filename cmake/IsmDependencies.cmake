# Third-party packages, found in CONFIG mode as Debian 12 ships them.
# CGAL comes last: its config prepends its own Find modules (see DEPENDENCIES.md).
find_package(Eigen3 3.4 CONFIG REQUIRED)
find_package(OpenMesh CONFIG REQUIRED) # no version file: never ask for a version
find_package(OpenEXR 3.1 CONFIG REQUIRED)
find_package(OpenImageIO 2.4 CONFIG REQUIRED)
find_package(draco 1.5 CONFIG REQUIRED)
find_package(TBB 2021 CONFIG REQUIRED)
find_package(CLI11 2.1 CONFIG REQUIRED)
find_package(nlohmann_json 3.11 CONFIG REQUIRED)
if(ISM_BUILD_TESTS)
  find_package(GTest 1.12 CONFIG REQUIRED)
endif()
if(ISM_BUILD_BENCH)
  find_package(benchmark 1.7 CONFIG REQUIRED)
endif()
set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE)
find_package(CGAL 5.5 CONFIG REQUIRED)

# Debian's OIIO target lists <prefix>/include/opencv4, absent without libopencv-dev.
foreach(_target OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
  foreach(_prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
    get_target_property(_value ${_target} ${_prop})
    if(_value)
      list(FILTER _value EXCLUDE REGEX "opencv4")
      set_target_properties(${_target} PROPERTIES ${_prop} "${_value}")
    endif()
  endforeach()
endforeach()
