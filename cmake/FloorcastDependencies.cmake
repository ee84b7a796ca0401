# Every dependency comes from a Debian 12 package (see scripts/install_deps.sh).
find_package(Threads REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
# OpenCV core and imgproc only: imgcodecs (GDAL, GDCM, OpenEXR, ...) and ximgproc (dnn, calib3d,
# ...) would be loaded by every floorcast process at start-up; PNG goes through libpng.
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc)
find_package(PNG REQUIRED)
find_package(ZLIB REQUIRED)
find_package(embree 3 REQUIRED)
find_package(TinyGLTF REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(pugixml 1.13 REQUIRED)
# Coordinate reference systems of geographic floor-plan sources (floorplans_import only).
find_package(PROJ 9 REQUIRED CONFIG)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(TBB REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(OSMesa REQUIRED IMPORTED_TARGET GLOBAL osmesa)
pkg_check_modules(FFTW3F REQUIRED IMPORTED_TARGET GLOBAL fftw3f)

# PCL 1.13 pulls VTK 9.1, whose imported targets reference MPI::MPI_C.
find_package(MPI REQUIRED COMPONENTS C)
find_package(PCL 1.13 REQUIRED COMPONENTS common kdtree search sample_consensus segmentation features)

# Header-only libraries shipped by Debian without CMake configs. The floorcast_* helper targets are
# IMPORTED, so the installed floorcastConfig.cmake can define them again (it includes this file)
# and the exported library targets may link them.
find_path(LBFGSPP_INCLUDE_DIR NAMES LBFGSB.h REQUIRED)
if(NOT TARGET floorcast_lbfgspp)
  add_library(floorcast_lbfgspp INTERFACE IMPORTED GLOBAL)
  target_include_directories(floorcast_lbfgspp SYSTEM INTERFACE ${LBFGSPP_INCLUDE_DIR})
  target_link_libraries(floorcast_lbfgspp INTERFACE Eigen3::Eigen)
endif()

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
