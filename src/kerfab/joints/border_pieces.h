#pragma once
/// \file Internal to the joints stage: every part's flattened outline as a ring of edges, and the
/// borders ("pieces") where two part sides meet, each side as a run of ring edges parametrised by
/// 3D arc length from the border's common end. Shared by the box/tab joints and the glue tabs.
#include <array>
#include <utility>
#include <vector>

#include "kerfab/core/geometry2d.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/strips/strips.h"

namespace kerfab::border {

/// One patch's outline in the plane, counter-clockwise.
struct Ring {
  std::vector<OutlineEdge> edges;  // counter-clockwise order
  std::vector<Vec2> start, end;    // 2D endpoints of each edge
  std::vector<Vec2> normal;        // outward unit normal of each edge
  std::vector<int> piece;          // border piece of each edge, -1 if unmated
  std::vector<int> piece_side;     // which side of that piece
};

/// One patch side of a border piece.
struct Side {
  int patch = -1, key = -1;     // key: patch * 4 + outline side, orders the two sides
  std::vector<int> ring_edges;  // in piece order (from the common end)
  bool reversed = false;        // piece order runs against the ring
  std::vector<double> s;        // arc length at the polyline's vertices, piece order
  std::vector<Vec3> n0, n1;     // per edge: part normal at its start and end (piece order)
  /// Index (into ring_edges, s - 1) of the edge arc length \p at falls on (the first or last
  /// edge beyond the ends).
  int edge_at(double at) const;
  /// The part normal at arc length \p at (interpolated along the edge it falls on).
  Vec3 normal_at(double at) const;
};

struct Piece {
  int edge = -1;
  std::vector<int> edges;  // the coarse edges of the border (a chain)
  std::array<Side, 2> sides;
  double length = 0;
  /// Fold angle between the two sides at arc length \p s [rad], 0 = coplanar.
  double fold_at(double s) const;
};

struct Pieces {
  std::vector<Ring> rings;                // per patch
  std::vector<Piece> pieces;              // every shared border
  std::vector<std::vector<int>> locals;   // per patch: Patch::local_vertices()
};

/// Rings of all patches and the border pieces between them. Consecutive coarse edges along which
/// the same two patch sides meet form one piece (a chain); a chain that closes into a loop stays
/// in coarse edges. \pre \p flat was computed from \p strips.
Pieces make_pieces(const Strips& strips, const Flattening& flat);

/// 3D end points of piece \p piece: where its first side's run of ring edges starts and where it
/// ends (the same point twice for a border that closes on itself).
std::array<Vec3, 2> piece_ends(const Strips& strips, const Pieces& pieces, int piece);

/// Arc length range along the piece of ring edge \p k of \p side [mm].
std::pair<double, double> s_range(const Side& side, int k);
/// Arc length along the piece of ring edge \p k's parameter \p t (0 at the edge's ring start).
double s_of(const Side& side, int k, double t);

/// Spherical interpolation of unit normals.
Vec3 slerp_normal(const Vec3& a, const Vec3& b, double t);

}  // namespace kerfab::border
