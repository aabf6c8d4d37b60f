#pragma once
/// \file assess.hpp
/// Map evaluation against a reference (a floor plan, a laser-scanner map): where a map is wrong
/// and by how much (wall error both ways, the warp's displacement per area), how broken (rigid
/// pieces), how complete (coverage) and how consistently connected (topology). docs/assessment.md.
///
/// \code
/// const areamatch::MapAssessment a = areamatch::assess_map(areamatch::Matcher<>{}, slam_map, floor_plan);
/// if (a.ok) std::cout << a.rigid_walls.map_to_reference.median_m << " m, "
///                     << a.brokenness.broken_pieces() << " broken pieces, "
///                     << a.coverage.explored_share << " explored\n";
/// \endcode

#include "assess/coverage.hpp"
#include "assess/params.hpp"
#include "assess/picture.hpp"
#include "assess/pieces.hpp"
#include "assess/report.hpp"
#include "assess/wall_error.hpp"
