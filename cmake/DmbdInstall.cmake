# `cmake --install`: the libraries, their headers, the `dmbd` program, the robot
# folders (robots/), a CMake package (find_package(dmbd) giving dmbd::base, dmbd::blocks, … with
# their dependencies) and a pkg-config file (dmbd.pc). docs/library.md says how to use
# them. Included from the top-level CMakeLists.txt after every module is defined.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# Every library, in link order (a library before those it uses).
set(DMBD_INSTALLED_MODULES report scenario experiments control sim viz wholebody model codegen diagrams blocks base)

foreach(m IN LISTS DMBD_INSTALLED_MODULES)
  set(t dmbd_${m})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${m})
  # The headers from the source tree while building, from the prefix once installed.
  set_property(TARGET ${t} PROPERTY INTERFACE_INCLUDE_DIRECTORIES
               $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/${m}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${m}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  list(APPEND DMBD_INSTALLED_TARGETS ${t})
  string(APPEND DMBD_PC_LIBS " -ldmbd_${m}")
  if(NOT TARGET dmbd::${m})
    add_library(dmbd::${m} ALIAS ${t})  # the same names inside this build as outside
  endif()
endforeach()

install(TARGETS ${DMBD_INSTALLED_TARGETS} EXPORT dmbdTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS dmbd RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${CMAKE_SOURCE_DIR}/robots/ DESTINATION ${CMAKE_INSTALL_DATADIR}/dmbd/robots
        PATTERN "make_*.py" EXCLUDE)

set(DMBD_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/dmbd)
install(EXPORT dmbdTargets NAMESPACE dmbd:: DESTINATION ${DMBD_CMAKE_DIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/dmbdConfig.cmake.in ${CMAKE_BINARY_DIR}/dmbdConfig.cmake
                              INSTALL_DESTINATION ${DMBD_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/dmbdConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/dmbdConfig.cmake ${CMAKE_BINARY_DIR}/dmbdConfigVersion.cmake DESTINATION ${DMBD_CMAKE_DIR})

# pkg-config: static libraries, so --libs lists every dependency (Requires, not
# Requires.private); the prefix is found from the .pc file's own place.
# Simbody's own .pc adds -std=c++11 to --cflags, which would override dmbd's -std=c++17;
# no dmbd header includes Simbody (it stays in model/src), so its libraries are listed
# directly, as its .pc gives them now.
find_package(PkgConfig REQUIRED)
execute_process(COMMAND ${PKG_CONFIG_EXECUTABLE} --libs simbody OUTPUT_VARIABLE DMBD_PC_SIMBODY_LIBS
                OUTPUT_STRIP_TRAILING_WHITESPACE COMMAND_ERROR_IS_FATAL ANY)
configure_file(${CMAKE_SOURCE_DIR}/cmake/dmbd.pc.in ${CMAKE_BINARY_DIR}/dmbd.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/dmbd.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
