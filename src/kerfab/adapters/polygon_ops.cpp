#include "kerfab/adapters/polygon_ops.h"

#include <cmath>
#include <polyclipping/clipper.hpp>

namespace kerfab {
namespace {

constexpr double kScale = 1e5;  // 10 nm per unit

ClipperLib::Path to_path(const Polygon2& p) {
  ClipperLib::Path out;
  out.reserve(p.size());
  for (const auto& v : p)
    out.emplace_back(static_cast<ClipperLib::cInt>(std::llround(v.x() * kScale)),
                     static_cast<ClipperLib::cInt>(std::llround(v.y() * kScale)));
  return out;
}

std::vector<Polygon2> from_paths(ClipperLib::Paths paths) {
  // Drop needle spikes and near-collinear vertices closer than 0.1 um to their neighbours'
  // segment: they are rounding debris, far below any cutter's resolution.
  ClipperLib::CleanPolygons(paths, 10.0);
  std::vector<Polygon2> out;
  for (const auto& path : paths) {
    if (path.size() < 3) continue;
    Polygon2 p;
    p.reserve(path.size());
    for (const auto& q : path)
      p.emplace_back(static_cast<double>(q.X) / kScale, static_cast<double>(q.Y) / kScale);
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace

std::vector<Polygon2> polygon_intersection(const Polygon2& a, const Polygon2& b) {
  ClipperLib::Clipper c;
  c.StrictlySimple(true);
  c.AddPath(to_path(a), ClipperLib::ptSubject, true);
  c.AddPath(to_path(b), ClipperLib::ptClip, true);
  ClipperLib::Paths out;
  c.Execute(ClipperLib::ctIntersection, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return from_paths(out);
}

std::vector<Polygon2> polygon_union(const std::vector<Polygon2>& polygons) {
  ClipperLib::Clipper c;
  c.StrictlySimple(true);
  for (const auto& p : polygons) c.AddPath(to_path(p), ClipperLib::ptSubject, true);
  ClipperLib::Paths out;
  c.Execute(ClipperLib::ctUnion, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return from_paths(out);
}

std::vector<Polygon2> polygon_difference(const std::vector<Polygon2>& a,
                                         const std::vector<Polygon2>& b) {
  ClipperLib::Clipper c;
  c.StrictlySimple(true);
  for (const auto& p : a) c.AddPath(to_path(p), ClipperLib::ptSubject, true);
  for (const auto& p : b) c.AddPath(to_path(p), ClipperLib::ptClip, true);
  ClipperLib::Paths out;
  c.Execute(ClipperLib::ctDifference, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return from_paths(out);
}

std::vector<Polygon2> polygon_offset(const std::vector<Polygon2>& polygons, double delta) {
  ClipperLib::ClipperOffset o(4.0);
  for (const auto& p : polygons)
    o.AddPath(to_path(p), ClipperLib::jtMiter, ClipperLib::etClosedPolygon);
  ClipperLib::Paths out;
  o.Execute(out, delta * kScale);
  return from_paths(out);
}

}  // namespace kerfab
