# Install and export rules: `cmake --install build --prefix P` installs the libraries, their
# headers, the CLI, the shipped data (share/floorcast) and a CMake package with one part per
# component, so another project can
#   find_package(floorcast REQUIRED COMPONENTS observe match)
#   target_link_libraries(app PRIVATE floorcast::match floorcast::observe)
# and needs only the packages those components (and the components they link) depend on: the
# installed config finds nothing else (tests/install checks it). Without COMPONENTS every
# component is loaded.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(FLOORCAST_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/floorcast)

# floorcast_install_library(NAME): the library into its own export set, its public headers under
# include/ (the build tree's <component>/include is the installed include/).
function(floorcast_install_library name)
  target_include_directories(${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  set_target_properties(${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME floorcast_${name})
  install(TARGETS ${name} EXPORT floorcast_${name}Targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(EXPORT floorcast_${name}Targets NAMESPACE floorcast:: DESTINATION ${FLOORCAST_INSTALL_CMAKEDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  set_property(GLOBAL APPEND PROPERTY FLOORCAST_INSTALLED_COMPONENTS ${name})
endfunction()

# The floorcast components and external packages a component's target links (PUBLIC and
# PRIVATE: a static library's private dependencies are link dependencies of its users).
function(floorcast_component_links name components_var packages_var)
  get_property(all GLOBAL PROPERTY FLOORCAST_INSTALLED_COMPONENTS)
  get_target_property(items ${name} LINK_LIBRARIES)
  if(NOT items)
    set(items "")
  endif()
  set(comps "")
  set(pkgs "")
  foreach(item IN LISTS items)
    string(REGEX REPLACE "^floorcast::" "" short "${item}")
    if(short IN_LIST all)
      list(APPEND comps ${short})
    else()
      floorcast_package_of_link_item("${item}" pkg)
      if(pkg)
        list(APPEND pkgs ${pkg})
      endif()
    endif()
  endforeach()
  list(REMOVE_DUPLICATES comps)
  list(REMOVE_DUPLICATES pkgs)
  set(${components_var} "${comps}" PARENT_SCOPE)
  set(${packages_var} "${pkgs}" PARENT_SCOPE)
endfunction()

# The package files, once every component has registered itself and its links (called at the end
# of the top level CMakeLists.txt). Also writes <build>/floorcast_link_graph.cmake, the graph the
# docs/architecture.md test checks the documented table against.
function(floorcast_install_package)
  get_property(all GLOBAL PROPERTY FLOORCAST_INSTALLED_COMPONENTS)
  set(table "")
  set(graph "# Generated at configure time from the targets' LINK_LIBRARIES (cmake/FloorcastInstall.cmake).\n")
  foreach(name IN LISTS all)
    floorcast_component_links(${name} comps pkgs)
    string(APPEND table "set(_floorcast_components_of_${name} \"${comps}\")\n")
    string(APPEND table "set(_floorcast_packages_of_${name} \"${pkgs}\")\n")
    string(APPEND graph "set(FLOORCAST_LINKS_${name} \"${comps}\")\nset(FLOORCAST_PACKAGES_${name} \"${pkgs}\")\n")
  endforeach()
  string(APPEND table "set(_floorcast_all_components \"${all}\")\n")
  string(APPEND graph "set(FLOORCAST_COMPONENT_TARGETS \"${all}\")\n")
  file(WRITE ${PROJECT_BINARY_DIR}/floorcast_link_graph.cmake "${graph}")
  set(FLOORCAST_COMPONENT_TABLE "${table}")
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/floorcastConfig.cmake.in
    ${PROJECT_BINARY_DIR}/floorcastConfig.cmake INSTALL_DESTINATION ${FLOORCAST_INSTALL_CMAKEDIR})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/floorcastConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/floorcastConfig.cmake ${PROJECT_BINARY_DIR}/floorcastConfigVersion.cmake
    ${PROJECT_SOURCE_DIR}/cmake/FloorcastPackages.cmake DESTINATION ${FLOORCAST_INSTALL_CMAKEDIR})
  # Shipped data the CLI finds at <prefix>/share/floorcast (scenarios/driver.hpp data_dir()).
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/floorplans/buildings DESTINATION ${CMAKE_INSTALL_DATADIR}/floorcast/floorplans)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenarios/ DESTINATION ${CMAKE_INSTALL_DATADIR}/floorcast/scenarios
    FILES_MATCHING PATTERN "*.yaml" PATTERN "*.md")
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/results/baselines DESTINATION ${CMAKE_INSTALL_DATADIR}/floorcast/results)
  # `floorcast figures` runs this script (matplotlib; it needs no compiled module).
  install(FILES ${PROJECT_SOURCE_DIR}/python/floorcast/figures.py DESTINATION ${CMAKE_INSTALL_DATADIR}/floorcast/python/floorcast)
endfunction()
