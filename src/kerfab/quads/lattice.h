#pragma once
/// \file Extraction of the quad lattice from a triangle surface carrying a position field
/// (internal to src/kerfab/quads): edges whose ends lie at the same lattice point are collapsed
/// (only where the link condition keeps the surface a manifold of the same topology, and no
/// triangle folds), the remaining triangles are paired into quads across lattice diagonals;
/// left-over triangles become quads in pairs along rows of split quads (pure mode, bridges.h)
/// or every face is split (quads into four, triangles into three); the irregular vertices are
/// then cleaned up (cleanup.h) and the quads smoothed and untangled.
#include <functional>
#include <vector>

#include "kerfab/core/mesh.h"
#include "kerfab/quads/dislocations.h"
#include "kerfab/quads/fields.h"

namespace kerfab::quads {

struct LatticeInput {
  const Surface* surface = nullptr;
  std::vector<Vec3> cross;                   ///< per vertex
  std::vector<Vec3> positions;               ///< per vertex: its lattice point
  std::vector<std::array<int, 2>> features;  ///< feature (sharp or border) edges
  double spacing = 0;                        ///< lattice spacing [mm]
  /// Pure: the paired quads, triangles left over made quads in pairs by splitting the row of
  /// quads between them (none if that fails);
  /// split: every face split (quads into 4, triangles into 3), only well-shaped pairs made;
  /// triangles: no collapse and no pairing, every triangle split into 3 quads (the safe net).
  enum class Mode { kPure, kSplit, kTriangles } mode = Mode::kPure;
  /// New points (split) land on the target and free vertices are smoothed along it; false:
  /// new points at plain midpoints and centres, nothing smoothed (every face stays convex).
  bool on_surface = true;
  /// Closest point on the target [mm] (the split's new points land there).
  std::function<Vec3(const Vec3&)> project;
  /// The target's unit normal at the closest point to a point (faces are untangled against it).
  std::function<Vec3(const Vec3&)> normal_at;
  /// Polish the quads: doublets (inner vertices of two quads) removed, and free vertices moved,
  /// each at most 0.4 of its mean edge, toward corners of 30 to 150 degrees and edges at least
  /// a quarter of their quad's mean edge (never making the worst quad around a vertex worse).
  bool polish = true;
  /// The lattice offsets between neighbours, as the dislocation step left them (edges whose
  /// ends share a lattice point collapse by these); null: measured from the positions.
  const IntegerLattice* offsets = nullptr;
  /// Vertices that stay corners of the quads besides those where feature lines meet or end (a
  /// border's sharp turns, quads.cpp).
  std::vector<int> corners;
};

struct LatticeResult {
  PolyMesh quads;  ///< all quads (after the split); empty when pure pairing left triangles
  int lattice_quads = 0;
  int lattice_triangles = 0;
  bool split = false;  ///< the faces were split (the quads are half the lattice spacing)
  int rows = 0;        ///< pure: rows of quads split to make left-over triangles quads (bridges.h)
  int rotations = 0, collapses = 0;  ///< pure: changes that removed irregular vertices (cleanup.h)
};

LatticeResult extract_quads(const LatticeInput& input);

}  // namespace kerfab::quads
