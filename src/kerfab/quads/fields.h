#pragma once
/// \file The fields behind the quad mesher (internal to src/kerfab/quads): principal
/// curvature by the normal cycle (Cohen-Steiner and Morvan 2003), a smooth cross field by one
/// sparse Hermitian solve (4-RoSy as in Knoeppel et al. 2013, with alignment terms), and a
/// position field whose lattice points are the quad corners (Jakob et al. 2015, Sec. 5).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "kerfab/core/mesh.h"

namespace kerfab::quads {

/// A triangle surface with what the fields need per vertex.
struct Surface {
  const TriangleMesh* mesh = nullptr;
  std::vector<Vec3> normals;                 ///< unit, area weighted
  std::vector<double> areas;                 ///< a third of the adjacent triangles' area [mm^2]
  std::vector<std::vector<int>> neighbours;  ///< one-ring vertices
};

Surface make_surface(const TriangleMesh& mesh);

/// Principal curvatures at every vertex over a ball of radius \p radius [mm].
struct Curvatures {
  std::vector<double> larger;        ///< |kappa| of the stronger principal curvature [1/mm]
  std::vector<double> smaller;       ///< |kappa| of the weaker one [1/mm]
  std::vector<Vec3> weak_direction;  ///< unit tangent of the weaker curvature (ruling direction)
};

/// \p stride: only at every stride-th vertex (the others stay 0), for a large mesh's statistics.
Curvatures principal_curvatures(const Surface& surface, double radius, int stride = 1);

/// Smooth cross field: per vertex a unit tangent q (the cross is q, n x q, -q, -n x q).
/// \p target_direction / \p weight: where weight > 0 the field is pulled towards that tangent
/// direction with that strength (features and borders large, curvature by its anisotropy);
/// with no weight anywhere the smoothest field.
std::vector<Vec3> cross_field(const Surface& surface, const std::vector<Vec3>& target_direction,
                              const std::vector<double>& weight);

/// The representative of the cross (q, n) best aligned with \p reference.
Vec3 aligned_cross(const Vec3& reference, const Vec3& q, const Vec3& n);
/// Its quarter turns: q turned k times about n (q, n x q, -q, -n x q), k in 0..3.
int aligned_turns(const Vec3& reference, const Vec3& q, const Vec3& n);

/// Where lattice lines must run (Jakob et al. 2015 hold a crease's positions on it): per vertex
/// the unit tangent of the feature line through it (zero: none), or a corner, where lines meet
/// or end, whose lattice point is the vertex itself.
struct PositionConstraints {
  std::vector<Vec3> line;
  std::vector<char> corner;
};

/// Position field: per vertex a lattice point o (spacing \p spacing [mm], axes q and n x q)
/// near the vertex, the lattices of neighbours made to agree. With \p constraints, a vertex on
/// a feature line keeps the lattice line along the cross axis nearest the feature's tangent
/// through itself, and a corner its lattice point on itself, so that quad edges run on them.
std::vector<Vec3> position_field(const Surface& surface, const std::vector<Vec3>& cross,
                                 double spacing, int iterations,
                                 const PositionConstraints* constraints = nullptr);

/// The lattice point of (o, q, qp) (spacing \p s [mm]) nearest to \p p.
Vec3 lattice_round(const Vec3& o, const Vec3& q, const Vec3& qp, const Vec3& p, double s);

/// The lattice offset from vertex i's lattice point to vertex j's, in i's axes [-], and how
/// well the two lattices agree across the edge: |gap| / spacing (small: consistent).
struct LatticeOffset {
  Eigen::Vector2i offset = Eigen::Vector2i::Zero();
  double gap = 0;
  /// The rest of the way from i's lattice point to j's beyond the offset, in i's axes [-]:
  /// j's lattice point is at offset + misfit cells (|misfit| = gap).
  Eigen::Vector2d misfit = Eigen::Vector2d::Zero();
};

LatticeOffset lattice_offset(const Vec3& pi, const Vec3& ni, const Vec3& qi, const Vec3& oi,
                             const Vec3& pj, const Vec3& nj, const Vec3& qj, const Vec3& oj,
                             double spacing);

}  // namespace kerfab::quads
