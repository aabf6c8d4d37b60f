#pragma once
/// \file areamatch.hpp
/// Umbrella header of the areamatch core (needs only Boost and Eigen). Map files (PGM, PNG,
/// ROS YAML) and SVG output are in <areamatch/io.hpp>, target `areamatch::io`.

#include "area_graph.hpp"
#include "assess.hpp"
#include "error.hpp"
#include "geometry.hpp"
#include "grid.hpp"
#include "image.hpp"
#include "matcher.hpp"
#include "merge.hpp"
#include "parameters.hpp"
#include "render.hpp"
#include "segment/voronoi_segmenter.hpp"
#include "segmenter.hpp"
#include "transform.hpp"
#include "version.hpp"
#include "warp.hpp"
