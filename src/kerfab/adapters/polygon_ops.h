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

/// The area \p a and \p b have in common: their intersection's, holes subtracted [mm^2].
double common_area(const Polygon2& a, const Polygon2& b);

/// Union of polygons (non-zero fill).
std::vector<Polygon2> polygon_union(const std::vector<Polygon2>& polygons);

/// Difference a minus b (non-zero fill).
std::vector<Polygon2> polygon_difference(const std::vector<Polygon2>& a,
                                         const std::vector<Polygon2>& b);

/// Outward offset by \p delta (negative: inward) with mitred corners (miter limit 4).
std::vector<Polygon2> polygon_offset(const std::vector<Polygon2>& polygons, double delta);

/// The same with round corners, each arc within \p tolerance of the true circle [mm]: the
/// points within |delta| of the polygons (delta > 0) or the points at least |delta| inside
/// them (delta < 0), as mathematical morphology grows and shrinks (a mitred corner reaches up to
/// four times farther).
std::vector<Polygon2> polygon_offset_round(const std::vector<Polygon2>& polygons, double delta,
                                           double tolerance);

}  // namespace kerfab
