# Every third-party package, found once for the whole tree.
find_package(Threads REQUIRED)
find_package(OpenMP REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
add_compile_definitions(BOOST_DLL_USE_STD_FS)
find_package(Boost 1.74 REQUIRED COMPONENTS filesystem system)
find_package(toml11 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 REQUIRED)
if(LISTA_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()

# Heavy packages: only plugins and tools link them, never liblista_sdk/core.
find_package(PCL 1.12 REQUIRED COMPONENTS common kdtree search io features filters
             segmentation sample_consensus surface registration)
find_package(octomap REQUIRED)
find_package(OpenVDB REQUIRED)
find_package(embree 3 REQUIRED)
find_package(Ceres REQUIRED)
find_package(Torch QUIET)
