#pragma once
/// \file detail/adjacency.hpp
/// Per-node lists of a graph in one array (compressed sparse rows). The skeleton's graphs have
/// ~10^5 nodes on a furnished map, where a vector (or a map entry) per node costs more than the
/// work done on them.

#include <cstddef>
#include <vector>

namespace areamatch::detail {

/// Node n's entries are entries[start[n], start[n + 1]), in the order their links were given.
template <class Index>
struct AdjacencyLists {
  std::vector<Index> start;
  std::vector<Index> entries;

  std::size_t degree(std::size_t node) const { return static_cast<std::size_t>(start[node + 1] - start[node]); }
  const Index* begin(std::size_t node) const { return entries.data() + start[node]; }
  const Index* end(std::size_t node) const { return entries.data() + start[node + 1]; }
};

/// One link: it adds `entry_a` to node `a`'s list, then `entry_b` to node `b`'s.
template <class Index>
struct LinkEnds {
  std::size_t a;
  Index entry_a;
  std::size_t b;
  Index entry_b;
};

/// The lists of `node_count` nodes from `link_count` links; `link(k)` returns link k's
/// `LinkEnds<Index>` (it is called twice per link: once to count, once to fill).
template <class Index, class Link>
AdjacencyLists<Index> build_adjacency(std::size_t node_count, std::size_t link_count, Link&& link) {
  AdjacencyLists<Index> lists;
  lists.start.assign(node_count + 1, Index{0});
  for (std::size_t k = 0; k < link_count; ++k) {
    const LinkEnds<Index> ends = link(k);
    ++lists.start[ends.a + 1];
    ++lists.start[ends.b + 1];
  }
  for (std::size_t n = 0; n < node_count; ++n) lists.start[n + 1] += lists.start[n];
  lists.entries.resize(static_cast<std::size_t>(lists.start.back()));
  std::vector<Index> filled(lists.start.begin(), lists.start.end() - 1);
  for (std::size_t k = 0; k < link_count; ++k) {
    const LinkEnds<Index> ends = link(k);
    lists.entries[static_cast<std::size_t>(filled[ends.a]++)] = ends.entry_a;
    lists.entries[static_cast<std::size_t>(filled[ends.b]++)] = ends.entry_b;
  }
  return lists;
}

}  // namespace areamatch::detail
