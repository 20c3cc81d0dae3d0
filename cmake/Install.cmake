# The library for other programs: the shared libusm.so beside the static
# libusm.a, and what `cmake --install` puts into the prefix:
#   lib/libusm.so.*, lib/libusm.a     usm::usm (shared), usm::usm_static
#   include/usm/*.h                   runtime API and generated kernels' headers
#                                     (#include <usm/usm.h>)
#   bin/usm                           the command (linked statically with usm_lib)
#   lib/cmake/usm/                    usmConfig.cmake, usmConfigVersion.cmake,
#                                     usmTargets*.cmake (find_package(usm))
#   lib/pkgconfig/usm.pc              pkg-config --cflags --libs usm
# Included from the top-level CMakeLists.txt after runtime/, so that every
# source and dependency given to usm_lib there is known.

include(CMakePackageConfigHelpers)

# 0.x releases may break the ABI with every minor version; later ones only
# with a major version.
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(USM_SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  set(USM_VERSION_COMPATIBILITY SameMinorVersion)
else()
  set(USM_SOVERSION ${PROJECT_VERSION_MAJOR})
  set(USM_VERSION_COMPATIBILITY SameMajorVersion)
endif()

# ---- shared library: usm_lib's (position-independent) objects ---------------
add_library(usm_shared SHARED $<TARGET_OBJECTS:usm_lib>)
add_dependencies(usm_shared usm_lib)
set_target_properties(usm_shared PROPERTIES
  OUTPUT_NAME usm EXPORT_NAME usm
  VERSION ${PROJECT_VERSION} SOVERSION ${USM_SOVERSION}
  LINKER_LANGUAGE C)
if(CMAKE_SYSTEM_NAME STREQUAL "Linux" AND NOT USM_SANITIZE)
  # A dependency that usm_lib has and usm_shared lacks fails here, not in a user's link.
  target_link_options(usm_shared PRIVATE LINKER:--no-undefined)
endif()
# usm_shared gets usm_lib's usage requirements, whatever runtime/ gave it.
foreach(_prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES
              INTERFACE_COMPILE_DEFINITIONS INTERFACE_COMPILE_OPTIONS
              INTERFACE_COMPILE_FEATURES)
  get_target_property(_v usm_lib ${_prop})
  if(_v)
    set_property(TARGET usm_shared PROPERTY ${_prop} "${_v}")
  endif()
endforeach()
get_target_property(_usm_links usm_lib INTERFACE_LINK_LIBRARIES)
if(NOT _usm_links)
  set(_usm_links "")
endif()
# The packages behind them: found here too (imported targets are visible only
# where they were found), and again in usmConfig.cmake (find_dependency).
set(USM_CONFIG_FIND_THREADS "")
set(USM_PC_THREADS "")
set(USM_PC_REQUIRES_PRIVATE "")
set(USM_CONFIG_FIND_PKGCONFIG "")
foreach(_item IN LISTS _usm_links)
  string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" _item "${_item}")
  if(_item MATCHES "^([A-Za-z0-9_]+)::")
    if(CMAKE_MATCH_1 STREQUAL "Threads")
      find_package(Threads REQUIRED)
      set(USM_CONFIG_FIND_THREADS "find_dependency(Threads)")
      if(CMAKE_THREAD_LIBS_INIT)   # empty where libc has the threads
        set(USM_PC_THREADS " ${CMAKE_THREAD_LIBS_INIT}")
      endif()
    elseif(CMAKE_MATCH_1 STREQUAL "PkgConfig")
      # pkg_check_modules(NAME ... IMPORTED_TARGET name): the module is NAME in lower case
      string(REGEX REPLACE "^PkgConfig::" "" _mod "${_item}")
      string(TOLOWER "${_mod}" _pcname)
      if(NOT TARGET ${_item})
        find_package(PkgConfig REQUIRED)
        pkg_check_modules(${_mod} REQUIRED IMPORTED_TARGET ${_pcname})
      endif()
      string(APPEND USM_PC_REQUIRES_PRIVATE " ${_pcname}")
      string(APPEND USM_CONFIG_FIND_PKGCONFIG
             "pkg_check_modules(${_mod} REQUIRED QUIET IMPORTED_TARGET ${_pcname})\n")
    elseif(NOT CMAKE_MATCH_1 MATCHES "^(GSL|SUNDIALS)$")
      message(FATAL_ERROR "usm_lib links ${_item}: find its package in cmake/Install.cmake and "
                          "cmake/usmConfig.cmake.in, and add its library to cmake/usm.pc.in")
    endif()
  endif()
endforeach()
if(USM_CONFIG_FIND_PKGCONFIG)
  set(USM_CONFIG_FIND_PKGCONFIG "find_dependency(PkgConfig)\n${USM_CONFIG_FIND_PKGCONFIG}")
endif()
foreach(_item IN LISTS _usm_links)
  if(_item MATCHES "^\\$<LINK_ONLY:(.*)>$")   # a PRIVATE dependency of usm_lib
    target_link_libraries(usm_shared PRIVATE ${CMAKE_MATCH_1})
  else()
    target_link_libraries(usm_shared PUBLIC ${_item})
  endif()
endforeach()

# What a project that adds this tree with add_subdirectory sees.
add_library(usm::usm ALIAS usm_shared)
add_library(usm::usm_static ALIAS usm_lib)

# ---- install ------------------------------------------------------------------
set(USM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/usm)

install(TARGETS usm_shared usm_lib EXPORT usmTargets
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
if(TARGET usm_cli)
  install(TARGETS usm_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
# share/usm: the data files the library reads (the report's, the plots';
# runtime/io/data_dir.h)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/usm)

# Public headers: runtime/include/usm/*.h and the generated kernels' headers, from the
# build tree when they are regenerated there.
file(GLOB USM_PUBLIC_RUNTIME_HEADERS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/runtime/include/usm/*.h)
list(SORT USM_PUBLIC_RUNTIME_HEADERS)
set(USM_PUBLIC_GENERATED_HEADERS "")
foreach(f IN LISTS USM_GENERATED_NAMES)
  # usm_equations.h: usm_equations' (below), not libusm's
  if(f MATCHES "\\.h$" AND (NOT f STREQUAL "usm_equations.h" OR TARGET usm_equations))
    list(APPEND USM_PUBLIC_GENERATED_HEADERS ${USM_GENERATED_DIR}/${f})
  endif()
endforeach()
install(FILES ${USM_PUBLIC_RUNTIME_HEADERS} ${USM_PUBLIC_GENERATED_HEADERS}
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/usm)

# The command's two further libraries, installed so that it includes installed
# headers only and a program can do what it does: usm::usm_equations (the
# equations documents, usm_equations.h) and, where MPI was found, usm::usm_mpi
# (the studies over MPI ranks, usm_mpi.h; usmConfig.cmake then finds MPI).
set(USM_CONFIG_FIND_MPI "")
foreach(_t usm_equations usm_mpi)
  if(TARGET ${_t})
    install(TARGETS ${_t} EXPORT usmTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  endif()
endforeach()
if(TARGET usm_mpi)
  install(FILES ${PROJECT_SOURCE_DIR}/runtime/mpi/usm_mpi.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/usm)
  set(USM_CONFIG_FIND_MPI "find_dependency(MPI COMPONENTS C)")
endif()

# CMake package.
install(EXPORT usmTargets NAMESPACE usm:: DESTINATION ${USM_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/usmConfig.cmake.in
  ${PROJECT_BINARY_DIR}/usmConfig.cmake
  INSTALL_DESTINATION ${USM_INSTALL_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/usmConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY ${USM_VERSION_COMPATIBILITY})
install(FILES ${PROJECT_BINARY_DIR}/usmConfig.cmake ${PROJECT_BINARY_DIR}/usmConfigVersion.cmake
  DESTINATION ${USM_INSTALL_CMAKEDIR})

# pkg-config file, written at install time for the prefix installed to
# (`cmake --install build --prefix DIR` may differ from CMAKE_INSTALL_PREFIX).
set(USM_PC_PREFIX "@USM_PC_INSTALL_PREFIX@")   # left for the install step
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(USM_PC_LIBDIR "${CMAKE_INSTALL_LIBDIR}")
else()
  set(USM_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
endif()
if(IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(USM_PC_INCLUDEDIR "${CMAKE_INSTALL_INCLUDEDIR}")
else()
  set(USM_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/usm.pc.in ${PROJECT_BINARY_DIR}/usm.pc.in @ONLY)
install(CODE "
  set(USM_PC_INSTALL_PREFIX \"\${CMAKE_INSTALL_PREFIX}\")
  configure_file(\"${PROJECT_BINARY_DIR}/usm.pc.in\" \"${PROJECT_BINARY_DIR}/usm.pc\" @ONLY)")
install(FILES ${PROJECT_BINARY_DIR}/usm.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
# How to link the library, and the example it describes (share/doc/usm)
install(FILES ${PROJECT_SOURCE_DIR}/docs/library.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${PROJECT_SOURCE_DIR}/examples/usm_example.c ${PROJECT_SOURCE_DIR}/examples/Makefile
  ${PROJECT_SOURCE_DIR}/examples/CMakeLists.txt DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples)
