# Install and export rules: `cmake --install build --prefix P` installs the libraries, their
# headers, the CLI, the shipped data (share/floorcast) and a CMake package, so another project can
#   find_package(floorcast REQUIRED)
#   target_link_libraries(app PRIVATE floorcast::match floorcast::observe)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(FLOORCAST_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/floorcast)

# floorcast_install_library(NAME): the library into the export set, its public headers under
# include/ (the build tree's <component>/include is the installed include/).
function(floorcast_install_library name)
  target_include_directories(${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  set_target_properties(${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME floorcast_${name})
  install(TARGETS ${name} EXPORT floorcastTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

# The package files, once every component has registered itself (called at the end of the top
# level CMakeLists.txt).
function(floorcast_install_package)
  install(EXPORT floorcastTargets NAMESPACE floorcast:: DESTINATION ${FLOORCAST_INSTALL_CMAKEDIR})
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/floorcastConfig.cmake.in
    ${PROJECT_BINARY_DIR}/floorcastConfig.cmake INSTALL_DESTINATION ${FLOORCAST_INSTALL_CMAKEDIR})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/floorcastConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/floorcastConfig.cmake ${PROJECT_BINARY_DIR}/floorcastConfigVersion.cmake
    ${PROJECT_SOURCE_DIR}/cmake/FloorcastDependencies.cmake DESTINATION ${FLOORCAST_INSTALL_CMAKEDIR})
  # Shipped data the CLI finds at <prefix>/share/floorcast (apps/cli_common.hpp source_dir()).
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/floorplans/buildings DESTINATION ${CMAKE_INSTALL_DATADIR}/floorcast/floorplans)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenarios/ DESTINATION ${CMAKE_INSTALL_DATADIR}/floorcast/scenarios
    FILES_MATCHING PATTERN "*.yaml" PATTERN "*.md")
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/results/baselines DESTINATION ${CMAKE_INSTALL_DATADIR}/floorcast/results)
  # `floorcast figures` runs this script (matplotlib; it needs no compiled module).
  install(FILES ${PROJECT_SOURCE_DIR}/python/floorcast/figures.py DESTINATION ${CMAKE_INSTALL_DATADIR}/floorcast/python/floorcast)
endfunction()
