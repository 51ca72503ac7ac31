#pragma once
/// \file The union of solids given by their closed triangle surfaces (CGAL Polygon Mesh
/// Processing's corefinement, exact constructions, behind this interface; no CGAL type leaks
/// out).
#include <optional>
#include <vector>

#include "kerfab/core/mesh.h"

namespace kerfab {

/// True when \p solid is a closed, manifold, outward-facing triangle surface that does not cross
/// itself: a surface CGAL can unite with another.
bool bounds_solid(const TriangleMesh& solid);

/// True when the solids bounded by the closed surfaces \p a and \p b meet: their surfaces
/// cross or touch (share a point), or one lies inside the other (tested exactly).
bool solids_meet(const TriangleMesh& a, const TriangleMesh& b);

/// The surface of the union of the solids \p a and \p b (each bounds_solid()), or nothing
/// where that union has no manifold surface (two solids meeting along an edge or at a point
/// only), CGAL cannot make it, or a triangle of it, rounded to doubles, has no area.
std::optional<TriangleMesh> solid_union(const TriangleMesh& a, const TriangleMesh& b);

}  // namespace kerfab
