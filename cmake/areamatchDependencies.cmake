# Finds what the areamatch targets need. Shared by the build tree and, through
# areamatchConfig.cmake, by consumers of the installed package.
include(GNUInstallDirs)
include(CMakeFindDependencyMacro)

# Boost >= 1.81: Boost.Polygon's Voronoi and Boost.Geometry. Header-only parts only.
find_package(Boost 1.81 REQUIRED CONFIG COMPONENTS headers)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
# merge_maps can match pairs on several threads (MergeParams::threads).
find_package(Threads REQUIRED)

if(AREAMATCH_WITH_IO)
  find_package(yaml-cpp REQUIRED CONFIG)
  # yaml-cpp 0.7 (Debian 12) names its target yaml-cpp; 0.8 adds yaml-cpp::yaml-cpp.
  if(TARGET yaml-cpp::yaml-cpp)
    set(AREAMATCH_YAML_TARGET yaml-cpp::yaml-cpp)
  else()
    set(AREAMATCH_YAML_TARGET yaml-cpp)
  endif()
  # stb is used header-only (its implementation is compiled static into each user).
  find_path(AREAMATCH_STB_INCLUDE_DIR NAMES stb/stb_image.h
            PATH_SUFFIXES include DOC "Directory holding stb/stb_image.h")
  if(NOT AREAMATCH_STB_INCLUDE_DIR)
    message(FATAL_ERROR "areamatch::io needs stb (Debian: apt-get install libstb-dev)")
  endif()
endif()
