#pragma once
/// \file segmentation_score.hpp
/// Room recall and precision of a segmentation against a hand-made room segmentation, as in
/// Bormann et al. 2016 (and `shared/tools/segscore.py`, which these functions agree with):
/// - recall: per ground-truth room, the largest share of it covered by one area, averaged;
/// - precision: per area, the largest share of it inside one ground-truth room, averaged.
/// Rooms and areas smaller than `min_cells` are ignored (200 cells = 0.5 m² at 0.05 m).
/// `segmentation_consistency` compares two segmentations of one building across maps.

#include "area_graph.hpp"
#include "detail/run_components.hpp"
#include "image.hpp"
#include "transform.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <vector>

namespace areamatch {

struct SegmentationScore {
  double recall = 0.0;
  double precision = 0.0;
  std::size_t rooms = 0;  ///< ground-truth rooms counted
  std::size_t areas = 0;  ///< areas counted
};

/// Ground-truth rooms of a Bormann-style segmentation image: 4-connected regions of near-white
/// pixels (8-bit value ≥ `white`), numbered from 0 in raster order; −1 elsewhere.
inline std::vector<int> rooms_from_image(const GreyImage& image, int white = 250) {
  std::vector<std::uint8_t> mask(image.values.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = image.value8(i) >= white;
  std::vector<int> rooms(mask.size(), -1);
  int next = 0;
  detail::for_each_run_component(mask, image.width, image.height, 1, false, [&](const detail::RunSpan& runs) {
    for (const auto& run : runs)
      std::fill(rooms.begin() + static_cast<std::ptrdiff_t>(run.row) * image.width + run.begin,
                rooms.begin() + static_cast<std::ptrdiff_t>(run.row) * image.width + run.end, next);
    ++next;
  });
  return rooms;
}

/// Scores `labels` (area id per cell, −1 for none) against `rooms` (room id per cell, −1 for
/// none); both of the same size.
inline SegmentationScore score_segmentation(const std::vector<int>& labels, const std::vector<int>& rooms,
                                            std::size_t min_cells = 200) {
  SegmentationScore score;
  if (labels.size() != rooms.size()) return score;
  std::map<int, std::size_t> room_size, area_size;
  std::map<std::pair<int, int>, std::size_t> overlap;  // (room, area) → cells
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (rooms[i] >= 0) ++room_size[rooms[i]];
    if (labels[i] >= 0) ++area_size[labels[i]];
    if (rooms[i] >= 0 && labels[i] >= 0) ++overlap[{rooms[i], labels[i]}];
  }
  std::map<int, std::size_t> best_for_room, best_for_area;
  for (const auto& [key, count] : overlap) {
    const auto [room, area] = key;
    best_for_room[room] = std::max(best_for_room[room], count);  // any area, as segscore.py
    if (room_size[room] >= min_cells) best_for_area[area] = std::max(best_for_area[area], count);
  }
  double recall = 0.0, precision = 0.0;
  for (const auto& [room, size] : room_size) {
    if (size < min_cells) continue;
    ++score.rooms;
    recall += static_cast<double>(best_for_room[room]) / size;
  }
  for (const auto& [area, size] : area_size) {
    if (size < min_cells) continue;
    ++score.areas;
    precision += static_cast<double>(best_for_area[area]) / size;
  }
  score.recall = score.rooms ? recall / score.rooms : 0.0;
  score.precision = score.areas ? precision / score.areas : 0.0;
  return score;
}

/// Cross-modal consistency of two segmentations of one building (`shared/tools/consistency.py`):
/// the share of destination areas of at least `min_cells` cells whose best source area, mapped
/// into the destination by `pixel_transform` (source pixel → destination pixel, nearest
/// neighbour), overlaps it with IoU ≥ 0.5. NaN when the destination has no such area.
inline double segmentation_consistency(const std::vector<int>& source_labels, int source_width, int source_height,
                                       const std::vector<int>& dest_labels, int dest_width, int dest_height,
                                       const PixelTransform& pixel_transform, std::size_t min_cells = 200) {
  // The source labels seen from every destination pixel.
  Eigen::Affine2d forward = Eigen::Affine2d::Identity();
  forward.matrix().topRows<2>() = pixel_transform;
  const Eigen::Affine2d backward = forward.inverse();
  std::vector<int> warped(dest_labels.size(), -1);
  for (int r = 0; r < dest_height; ++r)
    for (int c = 0; c < dest_width; ++c) {
      const Eigen::Vector2d p = backward * Eigen::Vector2d(c, r);
      const int sc = static_cast<int>(std::lround(p.x())), sr = static_cast<int>(std::lround(p.y()));
      if (sc >= 0 && sr >= 0 && sc < source_width && sr < source_height)
        warped[static_cast<std::size_t>(r) * dest_width + c] = source_labels[static_cast<std::size_t>(sr) * source_width + sc];
    }
  std::map<int, std::size_t> warped_size, dest_size;
  std::map<std::pair<int, int>, std::size_t> overlap;  // (dest area, source area) → cells
  for (std::size_t i = 0; i < dest_labels.size(); ++i) {
    if (warped[i] >= 0) ++warped_size[warped[i]];
    if (dest_labels[i] < 0) continue;
    ++dest_size[dest_labels[i]];
    if (warped[i] >= 0) ++overlap[{dest_labels[i], warped[i]}];
  }
  std::map<int, double> best_iou;
  for (const auto& [key, count] : overlap) {
    const double iou = static_cast<double>(count) / (dest_size[key.first] + warped_size[key.second] - count);
    best_iou[key.first] = std::max(best_iou[key.first], iou);
  }
  std::size_t counted = 0, consistent = 0;
  for (const auto& [area, size] : dest_size) {
    if (size < min_cells) continue;
    ++counted;
    consistent += best_iou[area] >= 0.5;
  }
  return counted ? static_cast<double>(consistent) / counted : std::numeric_limits<double>::quiet_NaN();
}

/// `score_segmentation` of a graph's labels.
inline SegmentationScore score_segmentation(const LabelImage& labels, const std::vector<int>& rooms, std::size_t min_cells = 200) {
  return score_segmentation(labels.to_vector(), rooms, min_cells);
}

/// `segmentation_consistency` of two graphs' labels.
inline double segmentation_consistency(const LabelImage& source_labels, int source_width, int source_height,
                                       const LabelImage& dest_labels, int dest_width, int dest_height,
                                       const PixelTransform& pixel_transform, std::size_t min_cells = 200) {
  return segmentation_consistency(source_labels.to_vector(), source_width, source_height, dest_labels.to_vector(),
                                  dest_width, dest_height, pixel_transform, min_cells);
}

}  // namespace areamatch
