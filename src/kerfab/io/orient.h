#pragma once
/// \file Consistent orientation of a polygon soup's faces: what a mesh file whose faces turn
/// different ways (an STL exported with some triangles flipped) needs before it is a surface
/// with an inside and an outside.
#include <string>
#include <vector>

#include "kerfab/core/mesh.h"

namespace kerfab {

struct OrientedFaces {
  /// The faces in the order given, some turned round (their first corner kept first).
  std::vector<std::vector<int>> faces;
  int turned = 0;      ///< faces whose corner order was reversed
  int components = 0;  ///< edge-connected pieces
  /// Every face once, each piece's faces in turn, each face after a piece's first sharing an
  /// edge with one before it: an order in which a half-edge mesh can take them.
  std::vector<int> order;
};

/// Turns faces round so that every edge two faces share is walked one way by one and the other
/// way by the other. Each closed piece (every edge on two faces) then faces outwards (positive
/// volume); an open piece keeps the way most of its faces (by count) were given.
/// \throw InvalidInput naming \p name: an edge on more than two faces (not manifold), or a
///        piece that no choice of turns makes consistent (one-sided, like a Möbius strip).
OrientedFaces orient_consistently(const std::vector<Vec3>& points,
                                  std::vector<std::vector<int>> faces, const std::string& name);

}  // namespace kerfab
