# Debian's libcpp-httplib-dev ships a compiled library, a header and a pkg-config
# file but no CMake package config; this module gives it the target name the
# upstream package uses (httplib::httplib) so the rest of the tree is unaware.
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(PC_HTTPLIB QUIET cpp-httplib)
endif()
find_path(httplib_INCLUDE_DIR httplib.h HINTS ${PC_HTTPLIB_INCLUDE_DIRS})
find_library(httplib_LIBRARY NAMES cpp-httplib HINTS ${PC_HTTPLIB_LIBRARY_DIRS})
set(httplib_VERSION ${PC_HTTPLIB_VERSION})
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(httplib
  REQUIRED_VARS httplib_INCLUDE_DIR httplib_LIBRARY
  VERSION_VAR httplib_VERSION)
if(httplib_FOUND AND NOT TARGET httplib::httplib)
  find_package(Threads REQUIRED)
  add_library(httplib::httplib UNKNOWN IMPORTED)
  set_target_properties(httplib::httplib PROPERTIES
    IMPORTED_LOCATION "${httplib_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${httplib_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES Threads::Threads)
  if(PC_HTTPLIB_CFLAGS_OTHER)
    set_property(TARGET httplib::httplib PROPERTY
      INTERFACE_COMPILE_OPTIONS ${PC_HTTPLIB_CFLAGS_OTHER})
  endif()
endif()
mark_as_advanced(httplib_INCLUDE_DIR httplib_LIBRARY)
