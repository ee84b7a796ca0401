# Every dependency comes from a Debian 12 package (see scripts/install_deps.sh).
include(${CMAKE_CURRENT_LIST_DIR}/FloorcastPackages.cmake)
foreach(_floorcast_package IN ITEMS Threads Eigen3 OpenCV PNG ZLIB embree TinyGLTF nlohmann_json pugixml PROJ yaml-cpp TBB
                                    OSMesa FFTW3F LBFGSpp)
  floorcast_find_package(${_floorcast_package})
endforeach()
# Boost.Geometry (header-only, private to core: no link item, so the installed config does not
# look for it): the R-tree of core/box_index.hpp.
find_package(Boost 1.74 REQUIRED)
# The `floorcast` CLI only (never a library dependency).
find_package(CLI11 REQUIRED)

# PCL 1.13 pulls VTK 9.1, whose imported targets reference MPI::MPI_C. PCL is linked by the
# observation module's back-end module only (loaded on first use), never by a library.
find_package(MPI REQUIRED COMPONENTS C)
find_package(PCL 1.13 REQUIRED COMPONENTS common kdtree search sample_consensus segmentation features)

if(FLOORCAST_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(FLOORCAST_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

# One interface target for the PCL components floorcast uses (not all of VTK), so include dirs,
# definitions and libraries travel together.
if(NOT TARGET floorcast_pcl)
  add_library(floorcast_pcl INTERFACE IMPORTED GLOBAL)
  target_include_directories(floorcast_pcl SYSTEM INTERFACE ${PCL_INCLUDE_DIRS})
  target_compile_definitions(floorcast_pcl INTERFACE ${PCL_DEFINITIONS})
  target_link_libraries(floorcast_pcl INTERFACE
    pcl_common pcl_kdtree pcl_search pcl_sample_consensus pcl_segmentation pcl_features pcl_filters
    FLANN::FLANN)
endif()
