#pragma once
/// \file Left-over triangles of a quad-dominant mesh made quads in pairs (internal to
/// src/kerfab/quads). Two triangles joined by a row of quads: every quad of the row is split in
/// two along the row, through the middles of the edges the row crosses, and each triangle gets
/// the middle of its crossed edge as a fourth corner. The mesh stays conforming, all its other
/// faces stay as they are, and only the row's two ends add irregular vertices (of valence 3); a
/// row that turns inside a quad splits it in three and adds one more. A row may also end on the
/// border (an open mesh may have an odd number of triangles). Rows are chosen greedily, the
/// cheapest of all first (one per quad split, three more per turn, one more per border end).
#include <array>
#include <functional>
#include <vector>

namespace kerfab::quads {

/// A vertex made by bridge_triangles: the mean of its first `count` sources (vertex ids, old or
/// made earlier in the list).
struct BridgeVertex {
  std::array<int, 4> from{};
  int count = 0;
  bool feature = false;  ///< the middle of a feature edge (it lies on the feature line)
};

struct BridgeResult {
  std::vector<std::vector<int>> faces;  ///< all quads when complete
  std::vector<BridgeVertex> added;      ///< ids from the input's vertex count on
  int rows = 0;                         ///< rows of quads split
  int turns = 0;                        ///< quads where a row turned (split in three)
  bool complete = false;                ///< no triangle left
};

/// \p faces: triangles and quads of a consistently oriented manifold mesh on vertices
/// 0..\p vertex_count-1; \p is_feature(a, b): the edge a-b lies on a feature line (its middle
/// is marked so, and so are the halves of a split feature edge).
BridgeResult bridge_triangles(std::vector<std::vector<int>> faces, int vertex_count,
                              const std::function<bool(int, int)>& is_feature);

}  // namespace kerfab::quads
