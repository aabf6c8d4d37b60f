#pragma once
/// \file detail/compact_voronoi.hpp
/// A Voronoi diagram that Boost.Polygon's builder fills, holding only what the skeleton reads.
///
/// `boost::polygon::voronoi_diagram` keeps a full half-edge structure (cell, vertex, twin, next,
/// prev and a colour per half-edge: 96 bytes an edge) and reserves room for six half-edges per
/// input site before duplicates are removed: about 120 MB for the 106 000 wall segments of a
/// 240 × 160 m floor, the largest piece of the heap while it was built. The skeleton reads each
/// edge's two sites, its two end vertices (by index and position), and whether it is primary and
/// curved; nothing walks around cells or vertices. This diagram keeps just that: 20 bytes an
/// edge, 16 a vertex, 8 a site.
///
/// It answers exactly as Boost's diagram does: the same vertices in the same order, the same
/// edges in the same order (test_segmentation compares them on walls of every kind). Boost's
/// `_build` removes edges whose ends coincide within 128 ulps, moving the edges of the removed
/// end onto the kept one by walking around it; here the ends are merged in a union-find, whose
/// roots are the vertices Boost's walk leaves in place. Vertices no edge starts at are dropped,
/// keeping the order, as Boost does.

#include <boost/polygon/voronoi.hpp>

#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

namespace areamatch::detail {

class CompactVoronoi {
 public:
  static constexpr std::uint32_t no_vertex = std::numeric_limits<std::uint32_t>::max();

  struct Vertex {
    double x = 0.0, y = 0.0;
  };
  /// The site of a cell: the index of its input segment and Boost's source category (a segment,
  /// its start point or its end point).
  struct Site {
    std::uint32_t source_index = 0;
    std::uint8_t category = 0;
    bool contains_point() const {
      return boost::polygon::belongs(static_cast<boost::polygon::SourceCategory>(category),
                                     boost::polygon::GEOMETRY_CATEGORY_POINT);
    }
  };
  /// An undirected edge: its two half-edges' sites (cells) and start vertices. Half-edge 0 runs
  /// from vertex[0] to vertex[1] with site[0] on its left, as Boost's even half-edge does.
  struct Edge {
    std::uint32_t site[2] = {0, 0};
    std::uint32_t vertex[2] = {no_vertex, no_vertex};
    bool primary = false;
    bool linear = false;
    bool is_finite() const { return vertex[0] != no_vertex && vertex[1] != no_vertex; }
    bool is_curved() const { return !linear; }
  };

  const std::vector<Site>& sites() const { return sites_; }
  const std::vector<Vertex>& vertices() const { return vertices_; }
  const std::vector<Edge>& edges() const { return edges_; }
  /// How many edges `_build` removed for ends that coincide (each merged two vertices).
  std::size_t removed_edges() const { return removed_edges_; }

  // --- The output interface of boost::polygon::voronoi_builder::construct ---------------------

  void _reserve(std::size_t num_sites) {
    // A diagram of n sites has at most 3n edges and 2n vertices; num_sites counts the segments'
    // end points before duplicates go, so it bounds n (untouched room costs no resident memory).
    sites_.reserve(num_sites);
    vertices_.reserve(2 * num_sites);
    edges_.reserve(3 * num_sites);
  }

  template <typename CT>
  void _process_single_site(const boost::polygon::detail::site_event<CT>& site) {
    sites_.push_back(site_record(site));
  }

  template <typename CT>
  std::pair<void*, void*> _insert_new_edge(const boost::polygon::detail::site_event<CT>& site1,
                                           const boost::polygon::detail::site_event<CT>& site2) {
    if (sites_.empty()) sites_.push_back(site_record(site1));
    sites_.push_back(site_record(site2));
    return push_edge(site1, site2);
  }

  template <typename CT1, typename CT2>
  std::pair<void*, void*> _insert_new_edge(const boost::polygon::detail::site_event<CT1>& site1,
                                           const boost::polygon::detail::site_event<CT1>& site3,
                                           const boost::polygon::detail::circle_event<CT2>& circle, void* data12,
                                           void* data23) {
    const auto vertex = static_cast<std::uint32_t>(vertices_.size());
    vertices_.push_back({circle.x(), circle.y()});
    start_of(data12) = vertex;
    start_of(data23) = vertex;
    const std::pair<void*, void*> halves = push_edge(site1, site3);
    edges_.back().vertex[1] = vertex;
    return halves;
  }

  void _build() {
    // Edges whose ends coincide go; the end vertex merges into the start vertex.
    std::vector<std::uint32_t> root(vertices_.size());
    std::iota(root.begin(), root.end(), 0u);
    auto find = [&](std::uint32_t v) {
      while (root[v] != v) v = root[v] = root[root[v]];
      return v;
    };
    const typename boost::polygon::voronoi_diagram_traits<double>::vertex_equality_predicate_type equal;
    using BoostVertex = boost::polygon::voronoi_vertex<double>;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < edges_.size(); ++i) {
      Edge edge = edges_[i];
      if (edge.is_finite()) {
        const std::uint32_t a = find(edge.vertex[0]), b = find(edge.vertex[1]);
        if (equal(BoostVertex(vertices_[a].x, vertices_[a].y), BoostVertex(vertices_[b].x, vertices_[b].y))) {
          root[b] = a;
          ++removed_edges_;
          continue;
        }
      }
      edges_[kept++] = edge;
    }
    edges_.resize(kept);
    edges_.shrink_to_fit();

    // Vertices that start a kept edge stay, in their order; every end becomes its merged vertex.
    std::vector<std::uint32_t> new_index(vertices_.size(), no_vertex);
    for (Edge& edge : edges_)
      for (std::uint32_t& v : edge.vertex)
        if (v != no_vertex) new_index[v = find(v)] = 0;
    std::uint32_t count = 0;
    for (std::size_t v = 0; v < vertices_.size(); ++v)
      if (new_index[v] != no_vertex) {
        new_index[v] = count;
        vertices_[count++] = vertices_[v];
      }
    vertices_.resize(count);
    vertices_.shrink_to_fit();
    for (Edge& edge : edges_)
      for (std::uint32_t& v : edge.vertex)
        if (v != no_vertex) v = new_index[v];
  }

 private:
  template <typename CT>
  static Site site_record(const boost::polygon::detail::site_event<CT>& site) {
    return {static_cast<std::uint32_t>(site.initial_index()), static_cast<std::uint8_t>(site.source_category())};
  }

  // Boost's voronoi_diagram::is_primary_edge and is_linear_edge.
  template <typename SiteEvent>
  static bool is_primary_edge(const SiteEvent& site1, const SiteEvent& site2) {
    const bool segment1 = site1.is_segment(), segment2 = site2.is_segment();
    if (segment1 && !segment2) return site1.point0() != site2.point0() && site1.point1() != site2.point0();
    if (!segment1 && segment2) return site2.point0() != site1.point0() && site2.point1() != site1.point0();
    return true;
  }
  template <typename SiteEvent>
  static bool is_linear_edge(const SiteEvent& site1, const SiteEvent& site2) {
    if (!is_primary_edge(site1, site2)) return true;
    return !(site1.is_segment() ^ site2.is_segment());
  }

  // A half-edge travels through the builder as an opaque handle: 1 + 2 × edge + side.
  static void* handle(std::size_t half_edge) { return reinterpret_cast<void*>(static_cast<std::uintptr_t>(half_edge + 1)); }
  std::uint32_t& start_of(void* half_edge) {
    const std::size_t h = static_cast<std::size_t>(reinterpret_cast<std::uintptr_t>(half_edge)) - 1;
    return edges_[h / 2].vertex[h % 2];
  }

  template <typename SiteEvent>
  std::pair<void*, void*> push_edge(const SiteEvent& site1, const SiteEvent& site2) {
    Edge edge;
    edge.site[0] = static_cast<std::uint32_t>(site1.sorted_index());
    edge.site[1] = static_cast<std::uint32_t>(site2.sorted_index());
    edge.primary = is_primary_edge(site1, site2);
    edge.linear = is_linear_edge(site1, site2);
    edges_.push_back(edge);
    const std::size_t first_half = 2 * (edges_.size() - 1);
    return {handle(first_half), handle(first_half + 1)};
  }

  std::vector<Site> sites_;
  std::vector<Vertex> vertices_;
  std::vector<Edge> edges_;
  std::size_t removed_edges_ = 0;
};

}  // namespace areamatch::detail
