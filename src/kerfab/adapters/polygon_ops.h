#pragma once
/// \file 2D polygon Booleans and offsets (Clipper behind this interface; no Clipper type leaks
/// out). Coordinates in millimetres, rounded internally to 10 nm. Boolean results are strictly
/// simple: polygons that would touch themselves at a vertex come out split there (in linear time
/// per ring; Clipper's own StrictlySimple is quadratic), and every ring's direction is checked
/// against the fill rule (outer rings counter-clockwise, holes clockwise).
#include <vector>

#include "kerfab/core/geometry2d.h"

namespace kerfab {

/// Intersection of two polygons (non-zero fill), as polygons (holes as clockwise rings).
std::vector<Polygon2> polygon_intersection(const Polygon2& a, const Polygon2& b);

/// Union of polygons (non-zero fill).
std::vector<Polygon2> polygon_union(const std::vector<Polygon2>& polygons);

/// Difference a minus b (non-zero fill).
std::vector<Polygon2> polygon_difference(const std::vector<Polygon2>& a,
                                         const std::vector<Polygon2>& b);

/// Outward offset by \p delta (negative: inward) with mitred corners (miter limit 4).
std::vector<Polygon2> polygon_offset(const std::vector<Polygon2>& polygons, double delta);

}  // namespace kerfab
