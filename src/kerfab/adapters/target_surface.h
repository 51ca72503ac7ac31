#pragma once
/// \file Closest-point, signed-distance and ray queries on the target surface (CGAL AABB tree
/// behind this interface; no CGAL type leaks out).
#include <memory>
#include <optional>
#include <vector>

#include "kerfab/core/mesh.h"

namespace kerfab {

/// Answer of a closest-point query.
struct SurfacePoint {
  Vec3 point;                  ///< closest point on the target [mm]
  double distance = 0;         ///< |query - point| [mm], >= 0
  double signed_distance = 0;  ///< +distance outside (normal side), -distance inside [mm]
  Vec3 normal;        ///< unit pseudo-normal at the closest point: the face normal inside a
                      ///< face, the mean of adjacent face normals on an edge, the
                      ///< angle-weighted normal at a vertex
  int triangle = -1;  ///< index of the triangle that holds the closest point
};

/// Answer of a ray query.
struct RayHit {
  Vec3 point;         ///< first intersection [mm]
  double t = 0;       ///< signed parameter along the (unit) direction [mm]
  int triangle = -1;  ///< index of the triangle hit
};

/// The target surface, prepared for fast queries. Immutable after construction; the query
/// functions are safe to call from several threads at once.
class TargetSurface {
 public:
  /// \pre mesh is a consistently oriented manifold triangle mesh (open boundaries allowed),
  ///      outward normals for a closed mesh. \throw InvalidInput no triangles or a zero-area one.
  explicit TargetSurface(const TriangleMesh& mesh);
  ~TargetSurface();
  TargetSurface(TargetSurface&&) noexcept;
  TargetSurface& operator=(TargetSurface&&) noexcept;

  /// Closest point on the surface, its distance, sign and pseudo-normal.
  SurfacePoint closest(const Vec3& query) const;

  /// Signed distance (positive on the side the normals point to) [mm].
  double signed_distance(const Vec3& query) const { return closest(query).signed_distance; }

  /// Intersection of the line origin + t * direction closest to the origin in |t|, with
  /// |t| <= max_distance. \pre direction has unit length.
  std::optional<RayHit> nearest_hit_along_line(const Vec3& origin, const Vec3& direction,
                                               double max_distance) const;

  /// Every intersection of the line origin + t * direction with |t| <= max_distance, nearest
  /// to the origin first, a crossing at an edge or vertex once (as the first of its triangles
  /// the tree finds; a segment lying in a triangle's plane is not counted).
  /// \pre direction has unit length.
  std::vector<RayHit> hits_along_line(const Vec3& origin, const Vec3& direction,
                                      double max_distance) const;

  /// Unit normal interpolated from area-weighted vertex normals (smooth shading normal).
  Vec3 smooth_normal(const SurfacePoint& at) const;

  const TriangleMesh& mesh() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// How far the vertices of \p mesh that faces use lie from \p target [mm] (0 where none).
struct VertexDistances {
  double max = 0, mean = 0;
};
VertexDistances vertex_distances(const PolyMesh& mesh, const TargetSurface& target);

}  // namespace kerfab
