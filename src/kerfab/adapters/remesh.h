#pragma once
/// \file Isotropic remeshing of a triangle surface with kept feature edges (CGAL's
/// Polygon Mesh Processing behind this interface; no CGAL type leaks out).
#include <array>
#include <vector>

#include "kerfab/core/mesh.h"

namespace kerfab {

/// A triangle mesh with a subset of its edges marked as features (sharp creases or borders).
struct FeatureTriangleMesh {
  TriangleMesh mesh;
  std::vector<std::array<int, 2>> features;  ///< vertex pairs, each an edge of `mesh`
  /// Vertices that stay where they are besides those where feature lines meet or end (a
  /// border's sharp turns); the remesher returns their new indices.
  std::vector<int> corners;
};

/// Remeshes \p input towards edges of length \p edge_length [mm] (> 0) in \p iterations rounds
/// of split, collapse, flip and tangential relaxation. Feature edges and border edges stay on
/// their polylines (they may be split or shortened along them) and come back marked as features;
/// vertices where feature lines meet or end and the corners given stay where they are (the
/// latter come back as corners); the surface's topology is kept. \pre input is a consistently
/// oriented manifold. \throw InvalidInput when the input is not a manifold triangle mesh CGAL
/// accepts.
FeatureTriangleMesh isotropic_remesh(const FeatureTriangleMesh& input, double edge_length,
                                     int iterations);

}  // namespace kerfab
