#pragma once
/// \file Plane geometry shared by the stages that work on flattened parts: points, polygons and
/// the strip coordinate along a flattened ladder.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace kerfab {

using Vec2 = Eigen::Vector2d;
using Polygon2 = std::vector<Vec2>;  ///< closed, last vertex not repeated

/// z component of the cross product of two plane vectors.
inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Signed area (counter-clockwise positive) [mm^2].
double polygon_area(const Polygon2& polygon);

/// Reverses \p polygon if it runs clockwise (Clipper's non-zero filling wants every polygon
/// counter-clockwise, or overlaps cancel out).
void make_counter_clockwise(Polygon2& polygon);

/// The part of convex polygon \p convex with (p - at).m <= 0.
Polygon2 clip_half_plane(const Polygon2& convex, const Vec2& at, const Vec2& m);

/// What the edge from \p a to \p b adds to the winding number round \p p: +1 or -1 where it
/// crosses the horizontal through \p p upwards with \p p on its left or downwards with \p p
/// on its right, else 0 (the cross product is formed only for edges crossing it).
inline int winding_step(const Vec2& a, const Vec2& b, const Vec2& p) {
  const bool a_below = a.y() <= p.y();
  if (a_below == (b.y() <= p.y())) return 0;
  const double c = cross2(b - a, p - a);
  return a_below ? (c > 0 ? 1 : 0) : (c < 0 ? -1 : 0);
}

/// Whether \p p lies inside \p polygons (non-zero winding over all their rings).
bool inside(const Vec2& p, const std::vector<Polygon2>& polygons);
/// Whether \p p lies inside \p polygon (non-zero winding).
bool inside(const Vec2& p, const Polygon2& polygon);

/// Distance from \p p to the segment from \p a to \p b [mm].
double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b);

/// Distance from \p p to the boundary of \p polygon [mm].
double distance_to_boundary(const Vec2& p, const Polygon2& polygon);

/// True when \p outline holds a point farther than \p depth [mm] from each of its edges:
/// looked for at 1.5, 2, 3 and 5 times \p depth in from the middles of its eight longest edges
/// (a strip's middle line is found at once). Sufficient, not necessary: false says nothing. Where
/// true, an offset of the outline inward by up to half \p depth is not empty, whatever its
/// joins (a mitre reaches at most twice the offset from the outline, so the offset path never
/// passes such a point, which keeps its winding number): the cheap half of a width test.
bool holds_point_deeper_than(const Polygon2& outline, double depth);

/// The polygon of largest positive area among \p polygons (holes, clockwise, never), or an
/// empty polygon if none has a positive area.
Polygon2 largest_polygon(const std::vector<Polygon2>& polygons);

/// \p ring without needles narrower than \p width [mm] anywhere along them: a vertex where the
/// ring turns back by more than a right angle goes when the triangle it spans with its
/// neighbours is nowhere that wide (its smallest height is below \p width), and its neighbours
/// are then looked at again. Booleans leave such needles where the sides of the polygons they
/// combine nearly coincide; grown by half the kerf, each becomes a hair of material as wide as
/// the beam. A sharp corner whose sides part wider than \p width stays.
Polygon2 without_needles(Polygon2 ring, double width);

/// A flattened patch seen along its length: the strip coordinate is the arc length through the
/// rulings' midpoints (shared by the kerf cuts and the labels placed between them).
struct StripFrame {
  const std::vector<Vec2>& x;  ///< the patch's flattened points, 2 * ruling + rail
  int n;                       ///< sub-quads
  std::vector<double> s;       ///< strip coordinate of each ruling [mm]
  StripFrame(const std::vector<Vec2>& points, int faces);
  Vec2 mid(int ruling) const { return 0.5 * (x[2 * ruling] + x[2 * ruling + 1]); }
  /// The sub-quad holding strip coordinate \p at (clamped to the strip).
  int face_at(double at) const;
  /// The two rail points of the cross-section at \p at.
  std::array<Vec2, 2> section(double at) const;
  /// Unit direction along the strip at \p at.
  Vec2 along(double at) const;
};

}  // namespace kerfab
