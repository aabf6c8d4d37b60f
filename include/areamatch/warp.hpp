#pragma once
/// \file warp.hpp
/// Non-rigid alignment: from a match's rigid answer, a smooth warp that bends the source map's
/// walls onto the destination's (a bent SLAM map or hand-held scan onto its floor plan), applied
/// to points forwards (`WarpField::apply`) and backwards (`WarpField::inverse`), and to a whole
/// map (`resample_through`). docs/warp.md.
///
/// \code
/// const areamatch::MapPairRun run = areamatch::match_map_files("scan.yaml", "plan.yaml");
/// if (run.result.ok) {
///   const areamatch::WarpResult warp = areamatch::fit_warp(run.source, run.dest, run.result.T_dest_source);
///   const Eigen::Vector2d on_plan = warp.field.apply(point_on_scan);  // world metres
/// }
/// \endcode

#include "warp/field.hpp"
#include "warp/fit.hpp"
#include "warp/params.hpp"
#include "warp/resample.hpp"
