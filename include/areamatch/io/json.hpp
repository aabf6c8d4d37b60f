#pragma once
/// \file io/json.hpp
/// JSON text for Area Graphs (what `areamatch segment --json` prints and `--graph` writes) and match results (what
/// `areamatch match --json` prints). Numbers are written so
/// that they read back exactly; keys and arrays come in a fixed order, so equal graphs give
/// equal text.

#include "../area_graph.hpp"
#include "../assess/report.hpp"
#include "../detail/format.hpp"
#include "../match/result.hpp"
#include "../merge.hpp"
#include "../warp/fit.hpp"

#include <string>
#include <utility>
#include <vector>

namespace areamatch {
namespace detail {

inline std::string json_quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

inline std::string json_point(double x, double y) { return "[" + format_double(x) + ", " + format_double(y) + "]"; }

template <class Ring>
std::string json_ring(const Ring& ring) {
  std::string out = "[";
  for (std::size_t i = 0; i < ring.size(); ++i) out += (i ? ", " : "") + json_point(ring[i].x(), ring[i].y());
  return out + "]";
}

}  // namespace detail

/// The graph as a JSON object: the map's frame, areas (polygon rings in metres, world frame,
/// outer ring first then holes; size; centroid; kind; passages) and passages.
inline std::string area_graph_json(const AreaGraph& graph) {
  using detail::format_double;
  using detail::json_point;
  std::string out = "{\n  \"map\": {\"width\": " + std::to_string(graph.grid.width) +
                    ", \"height\": " + std::to_string(graph.grid.height) +
                    ", \"resolution\": " + format_double(graph.grid.resolution) + ", \"origin\": [" +
                    format_double(graph.grid.origin.x) + ", " + format_double(graph.grid.origin.y) + ", " +
                    format_double(graph.grid.origin.yaw) + "]},\n";
  out += "  \"covered_fraction\": " + format_double(graph.covered_fraction) + ",\n  \"areas\": [";
  for (std::size_t i = 0; i < graph.areas.size(); ++i) {
    const Area& a = graph.areas[i];
    out += std::string(i ? "," : "") + "\n    {\"id\": " + std::to_string(a.id) + ", \"kind\": \"" + to_string(a.kind) +
           "\", \"size_m2\": " + format_double(a.size_m2) + ", \"centroid\": " + json_point(a.centroid.x(), a.centroid.y()) +
           ", \"max_clearance_m\": " + format_double(a.max_clearance_m) + ", \"passages\": [";
    for (std::size_t k = 0; k < a.passages.size(); ++k) out += (k ? ", " : "") + std::to_string(a.passages[k]);
    out += "], \"polygon\": [" + detail::json_ring(a.polygon.outer());
    for (const auto& hole : a.polygon.inners()) out += ", " + detail::json_ring(hole);
    out += "]}";
  }
  out += "\n  ],\n  \"passages\": [";
  for (std::size_t i = 0; i < graph.passages.size(); ++i) {
    const Passage& p = graph.passages[i];
    out += std::string(i ? "," : "") + "\n    {\"id\": " + std::to_string(p.id) + ", \"kind\": \"" + to_string(p.kind) +
           "\", \"position\": " + json_point(p.position.x(), p.position.y()) + ", \"width_m\": " +
           format_double(p.width_m) + ", \"areas\": [" + std::to_string(p.area_a) + ", " + std::to_string(p.area_b) +
           "], \"line\": [" + json_point(p.line.first.x(), p.line.first.y()) + ", " +
           json_point(p.line.second.x(), p.line.second.y()) + "]}";
  }
  return out + "\n  ]\n}\n";
}

namespace detail {
/// A number, or null when it is not finite (JSON has no NaN).
inline std::string json_number(double value) { return std::isfinite(value) ? format_double(value) : "null"; }

/// [[a, b, tx], [c, d, ty]]
inline std::string json_pixel_transform(const PixelTransform& m) {
  return "[[" + json_number(m(0, 0)) + ", " + json_number(m(0, 1)) + ", " + json_number(m(0, 2)) + "], [" +
         json_number(m(1, 0)) + ", " + json_number(m(1, 1)) + ", " + json_number(m(1, 2)) + "]]";
}
}  // namespace detail

/// A match result as one JSON object on one line: ok, reason and rejection (when not ok: "different
/// places", "not sure" or "no answer", `Rejection`), the transform in
/// world terms (rotation_deg, translation_m, scale, reflected) and as pixel_transform, score,
/// margin and the two it is the least of, p_correct, matched_areas, statistics and timings (seconds).
inline std::string match_result_json(const MatchResult& r) {
  using detail::json_number;
  const Similarity2& T = r.T_dest_source;
  std::string out = "{\"ok\": " + std::string(r.ok ? "true" : "false");
  if (!r.ok) out += ", \"reason\": " + detail::json_quote(r.reason) + ", \"rejection\": \"" + to_string(r.rejection) + "\"";
  out += ", \"rotation_deg\": " + json_number(T.rotation * 180.0 / pi);
  out += ", \"translation_m\": [" + json_number(T.translation.x()) + ", " + json_number(T.translation.y()) + "]";
  out += ", \"scale\": " + json_number(T.scale) + ", \"scale_estimated\": " + (r.scale_estimated ? "true" : "false") +
         ", \"reflected\": " + (T.reflected ? "true" : "false");
  out += ", \"pixel_transform\": " + detail::json_pixel_transform(r.pixel_transform);
  out += ", \"score\": " + json_number(r.score) + ", \"margin\": " + json_number(r.margin) +
         ", \"ambiguous\": " + (r.ambiguous ? "true" : "false") + ", \"p_correct\": " + json_number(r.p_correct);
  out += ", \"margin_different\": " + json_number(r.margin_different) +
         ", \"margin_mirrored\": " + json_number(r.margin_mirrored);
  const MatchEvidence& e = r.evidence;
  out += ", \"evidence\": {\"agreement\": " + json_number(e.agreement) +
         ", \"wall_agreement\": " + json_number(e.wall_agreement) +
         ", \"reverse_wall_agreement\": " + json_number(e.reverse_wall_agreement) +
         ", \"forward_wall_agreement\": " + json_number(e.forward_wall_agreement) +
         ", \"free_iou\": " + json_number(e.free_iou) + ", \"source_on_dest\": " + json_number(e.source_on_dest) +
         ", \"dest_on_source\": " + json_number(e.dest_on_source) +
         ", \"passage_agreement\": " + json_number(e.passage_agreement) +
         ", \"room_agreement\": " + json_number(e.room_agreement) +
         ", \"overlap_m2\": " + json_number(e.overlap_m2) + ", \"turn_margin\": " + json_number(e.turn_margin) +
         ", \"occupied_wall_agreement\": " + json_number(e.occupied_wall_agreement) + "}";
  out += ", \"matched_areas\": [";
  for (std::size_t i = 0; i < r.matched_areas.size(); ++i) {
    const auto& a = r.matched_areas[i];
    out += std::string(i ? ", " : "") + "{\"source\": " + std::to_string(a.source) + ", \"dest\": " +
           std::to_string(a.dest) + ", \"overlap\": " + json_number(a.overlap) + ", \"iou\": " + json_number(a.iou) +
           ", \"local_rotation_deg\": " + json_number(a.T_dest_source.rotation * 180.0 / pi) +
           ", \"local_translation_m\": [" + json_number(a.T_dest_source.translation.x()) + ", " +
           json_number(a.T_dest_source.translation.y()) + "], \"wall_agreement\": " + json_number(a.wall_agreement) + "}";
  }
  const MatchStatistics& s = r.statistics;
  out += "], \"statistics\": {\"source_areas\": " + std::to_string(s.source_areas) +
         ", \"dest_areas\": " + std::to_string(s.dest_areas) + ", \"mutual_pairs\": " + std::to_string(s.mutual_pairs) +
         ", \"hypotheses\": " + std::to_string(s.hypotheses) + ", \"clusters\": " + std::to_string(s.clusters) +
         ", \"verified\": " + std::to_string(s.verified) + ", \"refined\": " + std::to_string(s.refined) +
         ", \"scales_tried\": " + std::to_string(s.scales_tried) + ", \"overlay_failures\": " +
         std::to_string(s.overlay_failures) + "}";
  const MatchTimings& t = r.timings;
  out += ", \"timings\": {\"segment_source_s\": " + json_number(t.segment_source_s) +
         ", \"segment_dest_s\": " + json_number(t.segment_dest_s) + ", \"match_s\": " + json_number(t.match_s) +
         ", \"total_s\": " + json_number(t.total_s) + ", \"prepare_s\": " + json_number(t.prepare_s) +
         ", \"features_s\": " + json_number(t.features_s) +
         ", \"hypotheses_s\": " + json_number(t.hypotheses_s) + ", \"clustering_s\": " + json_number(t.clustering_s) +
         ", \"selection_s\": " + json_number(t.selection_s) + "}}";
  return out;
}

namespace detail {

/// A warp's figures as JSON members (no braces), metres.
inline std::string warp_figures_json(const WarpResult& w) {
  return "\"source_wall_points\": " + std::to_string(w.source_wall_points) + ", \"paired_points\": " + std::to_string(w.paired_points) +
         ", \"rigid_median_m\": " + json_number(w.rigid_median_m) + ", \"rigid_p95_m\": " + json_number(w.rigid_p95_m) +
         ", \"warped_median_m\": " + json_number(w.warped_median_m) + ", \"warped_p95_m\": " + json_number(w.warped_p95_m) +
         ", \"median_displacement_m\": " + json_number(w.median_displacement_m) +
         ", \"max_displacement_m\": " + json_number(w.max_displacement_m);
}

}  // namespace detail

/// A warp's figures (what `areamatch warp --json` prints under "warp"), metres and seconds.
inline std::string warp_result_json(const WarpResult& w, const WarpParams& params, double warp_s) {
  using detail::json_number;
  return "{\"control_spacing_m\": " + json_number(params.control_spacing_m) + ", \"bend_length_m\": " +
         json_number(params.bend_length_m) + ", " + detail::warp_figures_json(w) + ", \"warp_s\": " + json_number(warp_s) + "}";
}

namespace detail {

inline std::string wall_error_json(const WallErrorStats& s) {
  return "{\"points\": " + std::to_string(s.points) + ", \"mean_m\": " + json_number(s.mean_m) + ", \"median_m\": " +
         json_number(s.median_m) + ", \"p95_m\": " + json_number(s.p95_m) + ", \"within_tolerance\": " +
         json_number(s.within_tolerance) + ", \"at_cap\": " + json_number(s.at_cap) + "}";
}

inline std::string wall_errors_json(const WallErrors& w) {
  return "{\"map_to_reference\": " + wall_error_json(w.map_to_reference) +
         ", \"reference_to_map\": " + wall_error_json(w.reference_to_map) + "}";
}

inline std::string int_list_json(const std::vector<int>& values) {
  std::string out = "[";
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + std::to_string(values[i]);
  return out + "]";
}

}  // namespace detail

/// A map assessment as one JSON object on one line (what `areamatch assess --json` prints):
/// ok (and reason), whether the decision was overridden, the match, the warp, wall errors both
/// ways under the rigid answer and under the warp, each map area's displacement, the pieces
/// (brokenness), coverage, topology and timings. Metres, degrees, seconds.
inline std::string assessment_json(const MapAssessment& a) {
  using detail::json_number;
  std::string out = "{\"ok\": " + std::string(a.ok ? "true" : "false");
  if (!a.ok) out += ", \"reason\": " + detail::json_quote(a.reason);
  out += ", \"decision_overridden\": " + std::string(a.decision_overridden ? "true" : "false");
  out += ", \"match\": " + match_result_json(a.match);
  if (a.ok) {
    out += ", \"warp\": " + warp_result_json(a.warp, a.params.warp, a.timings.warp_s);
    out += ", \"rigid_walls\": " + detail::wall_errors_json(a.rigid_walls);
    out += ", \"warped_walls\": " + detail::wall_errors_json(a.warped_walls);
    out += ", \"area_displacement\": [";
    for (std::size_t i = 0; i < a.area_displacement.size(); ++i) {
      const auto& d = a.area_displacement[i];
      out += std::string(i ? ", " : "") + "{\"area\": " + std::to_string(d.area) + ", \"median_m\": " + json_number(d.median_m) +
             ", \"max_m\": " + json_number(d.max_m) + "}";
    }
    out += "], \"brokenness\": {\"broken_pieces\": " + std::to_string(a.brokenness.broken_pieces()) + ", \"pieces\": [";
    for (std::size_t k = 0; k < a.brokenness.pieces.size(); ++k) {
      const RigidPiece& p = a.brokenness.pieces[k];
      out += std::string(k ? ", " : "") + "{\"areas\": " + detail::int_list_json(p.areas) + ", \"size_m2\": " +
             json_number(p.size_m2) + ", \"rotation_deg\": " + json_number(p.rotation_rad * 180.0 / pi) +
             ", \"shift_m\": " + json_number(p.shift_m) + ", \"wall_agreement\": " + json_number(p.wall_agreement) +
             ", \"transform\": {\"rotation_deg\": " + json_number(p.T_reference_map.rotation * 180.0 / pi) +
             ", \"translation_m\": [" + json_number(p.T_reference_map.translation.x()) + ", " +
             json_number(p.T_reference_map.translation.y()) + "]}}";
    }
    const Coverage& c = a.coverage;
    out += "]}, \"coverage\": {\"explored_share\": " + json_number(c.explored_share) + ", \"explored_m2\": " +
           json_number(c.explored_m2) + ", \"reference_m2\": " + json_number(c.reference_m2) + ", \"found\": " +
           std::to_string(c.found) + ", \"partly_found\": " + std::to_string(c.partly_found) + ", \"missed\": " +
           std::to_string(c.missed) + ", \"reference_areas\": [";
    for (std::size_t i = 0; i < c.reference_areas.size(); ++i) {
      const auto& r = c.reference_areas[i];
      out += std::string(i ? ", " : "") + "{\"area\": " + std::to_string(r.area) + ", \"explored_share\": " +
             json_number(r.explored_share) + ", \"state\": \"" + to_string(r.state) + "\", \"map_areas\": " +
             detail::int_list_json(r.map_areas) + "}";
    }
    out += "], \"extra_map_areas\": " + detail::int_list_json(c.extra_map_areas) +
           ", \"missing_passages\": " + detail::int_list_json(c.missing_passages) + "}";
    const TopologyConsistency& t = a.topology;
    out += ", \"topology\": {\"map_passages\": " + std::to_string(t.map_passages) + ", \"map_consistent\": " +
           std::to_string(t.map_consistent) + ", \"reference_passages\": " + std::to_string(t.reference_passages) +
           ", \"reference_consistent\": " + std::to_string(t.reference_consistent) + ", \"inconsistent_map_passages\": " +
           detail::int_list_json(t.inconsistent_map_passages) + "}";
  }
  out += ", \"timings\": {\"match_s\": " + json_number(a.timings.match_s) + ", \"warp_s\": " +
         json_number(a.timings.warp_s) + ", \"assess_s\": " + json_number(a.timings.assess_s) + ", \"total_s\": " +
         json_number(a.timings.total_s) + "}}";
  return out;
}

/// A merge result as one JSON object on one line (what `areamatch merge --json` prints): ok, the
/// reference, per map (in the order given) whether it was placed, why not, its transform to the
/// reference (`pixel_transform`: its pixels → the reference's pixels, as `areamatch match`), per
/// edge the two maps, p_correct, agreement, whether the fit used it and why not, the residual; and
/// the timings (seconds), `extra_timings` first. `names` name the maps (e.g. their paths).
inline std::string merge_result_json(const MergeResult& r, const std::vector<std::string>& names,
                                     const std::vector<std::pair<std::string, double>>& extra_timings = {}) {
  using detail::json_number;
  using detail::json_quote;
  auto name = [&](std::size_t i) { return json_quote(merge_map_name(names, i)); };
  std::string out = "{\"ok\": " + std::string(r.ok ? "true" : "false") + ", \"reference\": " + name(r.reference) + ", \"maps\": [";
  for (std::size_t i = 0; i < r.maps.size(); ++i) {
    const MergedMap& m = r.maps[i];
    out += std::string(i ? ", " : "") + "{\"path\": " + name(i) + ", \"placed\": " + (m.placed ? "true" : "false");
    if (!m.placed) {
      out += ", \"reason\": " + json_quote(m.reason) + "}";
      continue;
    }
    const Similarity2& T = m.T_reference_map;
    out += ", \"pixel_transform\": " + detail::json_pixel_transform(m.pixel_transform) +
           ", \"rotation_deg\": " + json_number(T.rotation * 180.0 / pi) + ", \"translation_m\": [" +
           json_number(T.translation.x()) + ", " + json_number(T.translation.y()) + "], \"scale\": " + json_number(T.scale) +
           ", \"reflected\": " + (T.reflected ? "true" : "false") + ", \"residual_m\": " + json_number(m.residual_m);
    if (m.warp) out += ", \"warp\": {" + detail::warp_figures_json(*m.warp) + "}";
    out += "}";
  }
  out += "], \"edges\": [";
  for (std::size_t i = 0; i < r.edges.size(); ++i) {
    const MergeEdge& e = r.edges[i];
    out += std::string(i ? ", " : "") + "{\"from\": " + name(e.source) + ", \"to\": " + name(e.dest) +
           ", \"ok\": " + (e.match.ok ? "true" : "false") + ", \"p_correct\": " + json_number(e.match.p_correct) +
           ", \"agreement\": " + json_number(e.match.evidence.agreement) + ", \"used\": " + (e.used ? "true" : "false") +
           ", \"residual_m\": " + json_number(e.residual_m);
    if (!e.used) out += ", \"note\": " + json_quote(e.note);
    out += "}";
  }
  out += "], \"merged\": {\"width\": " + std::to_string(r.merged.width()) + ", \"height\": " + std::to_string(r.merged.height()) +
         ", \"resolution\": " + json_number(r.merged.empty() ? 0.0 : r.merged.resolution()) + ", \"origin\": [" +
         json_number(r.merged.origin().x) + ", " + json_number(r.merged.origin().y) + ", " + json_number(r.merged.origin().yaw) + "], \"wall_cells\": " + std::to_string(r.double_walls.wall_cells) +
         ", \"doubled_wall_cells\": " + std::to_string(r.double_walls.doubled_cells) +
         ", \"doubled_share\": " + json_number(r.double_walls.share()) + "}";
  out += ", \"timings\": {";
  for (const auto& [key, seconds] : extra_timings) out += json_quote(key) + ": " + json_number(seconds) + ", ";
  const MergeTimings& t = r.timings;
  out += "\"matching_s\": " + json_number(t.matching_s) + ", \"refine_s\": " + json_number(t.refine_s) +
         ", \"fit_s\": " + json_number(t.fit_s) + ", \"warp_s\": " + json_number(t.warp_s) +
         ", \"fuse_s\": " + json_number(t.fuse_s) + ", \"merge_s\": " + json_number(t.total_s) + "}}";
  return out;
}

}  // namespace areamatch
