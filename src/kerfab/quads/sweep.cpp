#include "kerfab/quads/sweep.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "kerfab/core/geometry2d.h"

namespace kerfab::quads {
namespace {

/// Newell's sum over the polygon \p corners (in order): twice its area vector, the way it
/// faces.
Vec3 area_vector(const std::vector<Vec3>& corners) {
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = 0; i < corners.size(); ++i)
    sum += corners[i].cross(corners[(i + 1) % corners.size()]);
  return sum;
}

/// The sum of \p mesh's triangles' area vectors: the way it faces.
Vec3 facing_of(const TriangleMesh& mesh) {
  Vec3 sum = Vec3::Zero();
  for (const auto& t : mesh.triangles)
    sum += area_vector({mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]});
  return sum;
}

/// \p mesh as an extrusion along \p axis, where it is one (find_extrusion's conditions).
/// \p uses: the mesh's edge_uses(), counted on first need (most shapes fail before).
std::optional<Extrusion> extrusion_along(const TriangleMesh& mesh, const Vec3& axis,
                                         const std::vector<Vec3>& normals,
                                         const std::vector<double>& areas, double same_height,
                                         std::optional<std::map<std::pair<int, int>, int>>& uses) {
  const double cos_tol = std::cos(kAxisTolerance), sin_tol = std::sin(kAxisTolerance);
  std::vector<int> up, down;
  Extrusion e;
  e.axis = axis;
  double up_area = 0, down_area = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const double d = normals[t].dot(axis);
    if (d > cos_tol) {
      up.push_back(static_cast<int>(t));
      up_area += areas[t];
    } else if (d < -cos_tol) {
      down.push_back(static_cast<int>(t));
      down_area += areas[t];
    } else if (std::abs(d) < sin_tol) {
      e.wall_area += areas[t];
    } else {
      return std::nullopt;  // neither a cap nor the wall
    }
  }
  if ((up.empty() && down.empty()) || !(e.wall_area > 0)) return std::nullopt;
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
  for (const Vec3& v : mesh.vertices) {
    lowest = std::min(lowest, v.dot(axis));
    highest = std::max(highest, v.dot(axis));
  }
  // Every corner of a cap at the end it closes.
  const auto at_height = [&](const std::vector<int>& cap, double height) {
    for (int t : cap)
      for (int v : mesh.triangles[t])
        if (std::abs(mesh.vertices[v].dot(axis) - height) > same_height) return false;
    return true;
  };
  if (!at_height(up, highest) || !at_height(down, lowest)) {
    // Triangles that face into the solid: its top cap faces down.
    std::swap(up, down);
    std::swap(up_area, down_area);
    if (!at_height(up, highest) || !at_height(down, lowest)) return std::nullopt;
  }
  e.bottom = lowest;
  e.top = highest;
  e.top_cap = !up.empty();
  e.bottom_cap = !down.empty();
  if (!(e.top - e.bottom > 100 * same_height)) return std::nullopt;
  // Borders only where a cap is missing: a rim at that end.
  if (!uses) uses = edge_uses(mesh);
  for (const auto& [edge, n] : *uses) {
    if (n == 2) continue;
    if (n != 1) return std::nullopt;
    for (int v : {edge.first, edge.second}) {
      const double h = mesh.vertices[v].dot(axis);
      const bool open_top = !e.top_cap && std::abs(h - e.top) <= same_height;
      const bool open_bottom = !e.bottom_cap && std::abs(h - e.bottom) <= same_height;
      if (!open_top && !open_bottom) return std::nullopt;
    }
  }
  // The same outline at both ends.
  if (e.top_cap && e.bottom_cap && std::abs(up_area - down_area) > 1e-3 * up_area)
    return std::nullopt;
  e.cap_on_top = e.top_cap;
  e.cap = sub_mesh(mesh, e.cap_on_top ? up : down);
  e.cap_area = e.cap_on_top ? up_area : down_area;
  e.cap_facing = facing_of(e.cap);
  return e;
}

/// The vertices of \p mesh's \p edges (pairs) in loops, each in order; empty where a vertex has
/// other than two of them.
std::vector<std::vector<int>> loops_of(const std::vector<std::array<int, 2>>& edges) {
  std::map<int, std::vector<int>> next;
  for (const auto& [a, b] : edges) {
    next[a].push_back(b);
    next[b].push_back(a);
  }
  std::vector<std::vector<int>> loops;
  std::map<int, bool> seen;
  for (const auto& [start, around] : next) {
    if (around.size() != 2) return {};
    if (seen[start]) continue;
    std::vector<int> loop{start};
    seen[start] = true;
    for (int previous = start, at = around[0]; at != start;) {
      if (seen[at]) return {};
      seen[at] = true;
      loop.push_back(at);
      const std::vector<int>& n = next.at(at);
      const int to = n[0] == previous ? n[1] : n[0];
      previous = at, at = to;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

/// A star-shaped outline about the origin (vertices in the plane across a loft's axis, in
/// order of their angle): where a ray from the origin meets it.
class StarOutline {
 public:
  /// False where \p points (about the origin) do not go once round it, angle rising.
  bool set(std::vector<Vec2> points) {
    const auto turn = [](const Vec2& a, const Vec2& b) {
      return std::atan2(cross2(a, b), a.dot(b));
    };
    const int n = static_cast<int>(points.size());
    if (n < 3) return false;
    double total = 0;
    for (int i = 0; i < n; ++i) total += turn(points[i], points[(i + 1) % n]);
    if (total < 0) std::reverse(points.begin(), points.end());
    points_ = std::move(points);
    way_.assign(n + 1, 0.0);
    for (int i = 0; i < n; ++i) {
      const double t = turn(points_[i], points_[(i + 1) % n]);
      if (!(t > 1e-9)) return false;  // back or along a ray: not star-shaped about the origin
      way_[i + 1] = way_[i] + t;
    }
    return std::abs(way_[n] - 2 * std::numbers::pi) < 1e-6;
  }
  /// The edge the ray through \p q meets, plus how far along it (0 to 1), and the distance
  /// from the origin to where it meets it.
  std::pair<double, double> at(const Vec2& q) const {
    const int n = static_cast<int>(points_.size());
    const Vec2& p0 = points_[0];
    double a = std::atan2(cross2(p0, q), p0.dot(q));
    if (a < 0) a += 2 * std::numbers::pi;
    const int i = std::clamp(
        static_cast<int>(std::upper_bound(way_.begin(), way_.end(), a) - way_.begin()) - 1, 0,
        n - 1);
    const Vec2 pi = points_[i], edge = points_[(i + 1) % n] - pi, dir = q.normalized();
    const double denominator = cross2(dir, edge);
    const double lambda = std::abs(denominator) > 1e-300 ? -cross2(dir, pi) / denominator : 0.0;
    return {i + std::clamp(lambda, 0.0, 1.0), dir.dot(pi + lambda * edge)};
  }
  int size() const { return static_cast<int>(points_.size()); }

 private:
  std::vector<Vec2> points_;
  std::vector<double> way_;  // angle from points_[0] to each vertex, rising, 2 pi at the end
};

/// \p mesh as a loft along \p axis, where it is one (find_extrusion's second kind).
std::optional<Extrusion> loft_along(const TriangleMesh& mesh, const Vec3& axis,
                                    const std::vector<Vec3>& normals,
                                    const std::vector<double>& areas, double same_height,
                                    const std::map<std::pair<int, int>, int>& uses) {
  const int nv = static_cast<int>(mesh.vertices.size());
  const int nt = static_cast<int>(mesh.triangles.size());
  std::vector<int> order(nv);
  for (int i = 0; i < nv; ++i) order[i] = i;
  std::vector<double> height(nv);
  for (int i = 0; i < nv; ++i) height[i] = mesh.vertices[i].dot(axis);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return height[a] < height[b]; });
  std::vector<int> level(nv);
  std::vector<double> heights;
  for (int i : order) {
    if (heights.empty() || height[i] - heights.back() > same_height) heights.push_back(height[i]);
    level[i] = static_cast<int>(heights.size()) - 1;
  }
  if (heights.size() < 2 || static_cast<int>(heights.size()) > nv / 3) return std::nullopt;
  // Flat triangles (caps, and the flat steps between two rings at one height) face along the
  // axis; every other triangle lies between two neighbouring heights (the wall).
  const double cos_tol = std::cos(kAxisTolerance);
  std::vector<int> flat, wall;
  double wall_area = 0;
  for (int t = 0; t < nt; ++t) {
    const auto& tr = mesh.triangles[t];
    const int lo = std::min({level[tr[0]], level[tr[1]], level[tr[2]]});
    const int hi = std::max({level[tr[0]], level[tr[1]], level[tr[2]]});
    if (lo == hi && std::abs(normals[t].dot(axis)) > cos_tol) {
      flat.push_back(t);
    } else if (hi == lo + 1) {
      wall.push_back(t), wall_area += areas[t];
    } else {
      return std::nullopt;
    }
  }
  if (wall.empty()) return std::nullopt;
  // The rings: loops of the wall's edges along one height (a wall triangle has one).
  std::vector<std::array<int, 2>> along;
  for (int t : wall)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      if (level[a] == level[b]) along.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(along.begin(), along.end());
  along.erase(std::unique(along.begin(), along.end()), along.end());
  std::vector<std::vector<int>> rings = loops_of(along);
  if (rings.empty()) return std::nullopt;
  const int loops = static_cast<int>(rings.size());
  std::vector<int> ring_of(nv, -1);
  for (int r = 0; r < loops; ++r)
    for (int i : rings[r]) ring_of[i] = r;
  // Poles: wall vertices on no ring (a bowl's bottom, a sphere's poles, fanned to the ring
  // round them), each a ring of its own, on the axis (checked below) at scale 0.
  for (int t : wall)
    for (int i : mesh.triangles[t])
      if (ring_of[i] < 0) {
        ring_of[i] = static_cast<int>(rings.size());
        rings.push_back({i});
      }
  const auto is_pole = [&](int r) { return r >= loops; };
  for (int t : flat)
    for (int i : mesh.triangles[t])
      if (ring_of[i] >= 0 && is_pole(ring_of[i])) return std::nullopt;
  if (rings.size() < 2) return std::nullopt;
  const int nr = static_cast<int>(rings.size());
  const Vec3 u = axis.unitOrthogonal(), v = axis.cross(u);
  const auto flat2 = [&](int i) { return Vec2(mesh.vertices[i].dot(u), mesh.vertices[i].dot(v)); };
  // The outline every ring scales: the largest ring, about its centroid.
  std::vector<Polygon2> flat_rings(nr);
  std::vector<double> ring_area(nr);
  int largest = 0;
  for (int r = 0; r < nr; ++r) {
    for (int i : rings[r]) flat_rings[r].push_back(flat2(i));
    ring_area[r] = std::abs(polygon_area(flat_rings[r]));
    if (ring_area[r] > ring_area[largest]) largest = r;
  }
  if (!(ring_area[largest] > 0)) return std::nullopt;
  Vec2 centroid = Vec2::Zero();  // of the area it encloses
  const Polygon2& widest = flat_rings[largest];
  for (std::size_t i = 0; i < widest.size(); ++i) {
    const Vec2 &a = widest[i], &b = widest[(i + 1) % widest.size()];
    centroid += cross2(a, b) * (a + b) / 6.0;
  }
  centroid /= polygon_area(widest);
  std::vector<Vec2> outline;
  for (const Vec2& p : widest) outline.push_back(p - centroid);
  StarOutline star;
  if (!star.set(outline)) return std::nullopt;
  const int n = star.size();
  // Each ring's scale, and every vertex of it on the outline so scaled.
  const double tolerance = 10 * same_height;
  std::vector<double> along_outline(nv), scale(nr);
  for (int r = 0; r < nr; ++r) {
    if (is_pole(r)) {  // on the axis: within a thousandth of the diagonal
      if (!((flat2(rings[r][0]) - centroid).norm() <= 100 * same_height)) return std::nullopt;
      scale[r] = 0;
      continue;
    }
    std::vector<double> ratios;
    std::vector<double> reach;
    for (int i : rings[r]) {
      const Vec2 q = flat2(i) - centroid;
      if (!(q.norm() > tolerance)) return std::nullopt;  // on the axis
      const auto [at, distance] = star.at(q);
      if (!(distance > tolerance)) return std::nullopt;
      along_outline[i] = at;
      ratios.push_back(q.norm() / distance);
      reach.push_back(distance);
    }
    std::vector<double> sorted = ratios;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    scale[r] = sorted[sorted.size() / 2];
    for (std::size_t k = 0; k < ratios.size(); ++k)
      if (std::abs(ratios[k] - scale[r]) * reach[k] > tolerance) return std::nullopt;
  }
  // The rings joined by the wall (neighbouring heights) and by flat steps (one height); a flat
  // region touching one ring alone is a cap.
  std::map<std::pair<int, int>, bool> joins;
  for (int t : wall) {
    std::array<int, 3> r{};
    for (int k = 0; k < 3; ++k) r[k] = ring_of[mesh.triangles[t][k]];
    if (std::find(r.begin(), r.end(), -1) != r.end()) return std::nullopt;
    const int a = std::min({r[0], r[1], r[2]}), b = std::max({r[0], r[1], r[2]});
    if (a == b || !(r[0] == a || r[0] == b) || !(r[1] == a || r[1] == b) ||
        !(r[2] == a || r[2] == b))
      return std::nullopt;
    joins[{a, b}] = true;
  }
  // Flat regions: their triangles joined across edges.
  std::vector<int> region(nt, -1);
  std::vector<std::vector<int>> regions;
  {
    std::map<std::pair<int, int>, std::vector<int>> by_edge;
    for (int t : flat)
      for (int k = 0; k < 3; ++k) {
        const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
        by_edge[{std::min(a, b), std::max(a, b)}].push_back(t);
      }
    for (int t0 : flat) {
      if (region[t0] >= 0) continue;
      const int id = static_cast<int>(regions.size());
      regions.push_back({});
      std::vector<int> stack{t0};
      region[t0] = id;
      while (!stack.empty()) {
        const int t = stack.back();
        stack.pop_back();
        regions[id].push_back(t);
        for (int k = 0; k < 3; ++k) {
          const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
          for (int o : by_edge[{std::min(a, b), std::max(a, b)}])
            if (region[o] < 0) region[o] = id, stack.push_back(o);
        }
      }
      std::sort(regions[id].begin(), regions[id].end());  // the target's order
    }
  }
  std::map<int, std::vector<int>> caps;  // ring: its cap's triangles
  std::map<int, double> cap_area;
  for (const std::vector<int>& triangles : regions) {
    std::vector<int> touched;
    for (int t : triangles)
      for (int i : mesh.triangles[t])
        if (ring_of[i] >= 0 &&
            std::find(touched.begin(), touched.end(), ring_of[i]) == touched.end())
          touched.push_back(ring_of[i]);
    if (touched.size() == 2) {
      joins[{std::min(touched[0], touched[1]), std::max(touched[0], touched[1])}] = true;
    } else if (touched.size() == 1 && !caps.contains(touched[0])) {
      caps[touched[0]] = triangles;
      for (int t : triangles) cap_area[touched[0]] += areas[t];
    } else {
      return std::nullopt;
    }
  }
  // One path of rings from one end to the other.
  std::vector<std::vector<int>> next(nr);
  for (const auto& [pair, yes] : joins) {
    next[pair.first].push_back(pair.second);
    next[pair.second].push_back(pair.first);
  }
  std::vector<int> path;
  for (int r = 0; r < nr && path.empty(); ++r)
    if (next[r].size() == 1) path.push_back(r);
  if (path.empty()) return std::nullopt;  // a loop of rings (a torus)
  while (true) {
    const int at = path.back();
    if (next[at].size() > 2) return std::nullopt;
    int to = -1;
    for (int o : next[at])
      if (path.size() < 2 || o != path[path.size() - 2]) to = o;
    if (to < 0) break;
    path.push_back(to);
  }
  if (static_cast<int>(path.size()) != nr) return std::nullopt;
  for (const auto& [r, triangles] : caps)
    if (r != path.front() && r != path.back()) return std::nullopt;
  // From the lower end to the higher.
  const auto ring_height = [&](int r) { return heights[level[rings[r][0]]]; };
  if (!(std::abs(ring_height(path.back()) - ring_height(path.front())) > 100 * same_height))
    return std::nullopt;
  if (ring_height(path.back()) < ring_height(path.front())) std::reverse(path.begin(), path.end());
  Extrusion e;
  e.axis = axis;
  e.wall_area = wall_area;
  e.bottom = ring_height(path.front());
  e.top = ring_height(path.back());
  e.bottom_cap = caps.contains(path.front());
  e.top_cap = caps.contains(path.back());
  // Borders only on the rings at the ends without a cap.
  for (const auto& [edge, count] : uses) {
    if (count == 2) continue;
    if (count != 1) return std::nullopt;
    for (int i : {edge.first, edge.second}) {
      const int r = ring_of[i];
      if (!((r == path.front() && !e.bottom_cap) || (r == path.back() && !e.top_cap)))
        return std::nullopt;
    }
  }
  // Every wall triangle along one edge of the outline.
  const auto off = [&](double x, int edge) {  // x - edge, round the outline to [-n/2, n/2)
    double d = std::fmod(x - edge + 1.5 * n, static_cast<double>(n));
    if (d < 0) d += n;
    return d - 0.5 * n;
  };
  constexpr double kOnEdge = 1e-4;
  for (int t : wall) {
    const auto& tr = mesh.triangles[t];
    const int on_ring = is_pole(ring_of[tr[0]]) ? tr[1] : tr[0];  // a pole is on every edge
    const int first = static_cast<int>(std::floor(along_outline[on_ring]));
    bool one_edge = false;
    for (int edge : {first - 1, first, first + 1}) {
      const int k = ((edge % n) + n) % n;
      one_edge = std::all_of(tr.begin(), tr.end(), [&](int vi) {
        if (is_pole(ring_of[vi])) return true;
        const double d = off(along_outline[vi], k);
        return d >= -kOnEdge && d <= 1 + kOnEdge;
      });
      if (one_edge) break;
    }
    if (!one_edge) return std::nullopt;
  }
  // A pole's end is a dome up to the first ring of kDomeStop times the widest one's scale, the
  // scale rising all the way (the dome one height over the plane across the axis): the wall
  // runs between positions lo and hi of the path.
  // It ends sooner where the profile would steepen past kDomeSlope: no dome where it is that
  // steep at the pole (a cone's apex: the lattice takes the whole).
  int lo = 0, hi = nr - 1;
  const double widest_scale = *std::max_element(scale.begin(), scale.end());
  double mean_radius = 0;  // of the outline at scale 1
  for (const Vec2& p : outline) mean_radius += p.norm() / static_cast<double>(outline.size());
  const auto steep = [&](int a, int b) {  // the profile from path[a] to path[b]
    const double across = std::abs(scale[path[b]] - scale[path[a]]) * mean_radius;
    return std::abs(ring_height(path[b]) - ring_height(path[a])) > kDomeSlope * across;
  };
  const auto dome_end = [&](int from, int step) {
    int k = from + step;
    if (k < 0 || k >= nr || steep(from, k)) return -1;
    while (true) {
      if (!(scale[path[k]] > scale[path[k - step]])) return -1;
      if (scale[path[k]] >= kDomeStop * widest_scale) return k;
      const int after = k + step;
      if (after < 0 || after >= nr) return -1;
      if (steep(k, after)) return k;
      k = after;
    }
  };
  // A tip: a pole, or a flat cap on a ring under kLeastLoftScale of the widest (a sphere as
  // OpenSCAD writes one: its poles flat polygons a few degrees across), which no loft's scales
  // reach: its dome takes the cap in.
  const auto tip = [&](int r) {
    return is_pole(r) || (caps.contains(r) && scale[r] < kLeastLoftScale * widest_scale);
  };
  const bool bottom_tip = tip(path.front()), top_tip = tip(path.back());
  if (bottom_tip && (lo = dome_end(0, 1)) < 0) return std::nullopt;
  if (top_tip && (hi = dome_end(nr - 1, -1)) < 0) return std::nullopt;
  if (!(lo < hi)) return std::nullopt;
  if (bottom_tip) e.bottom = ring_height(path[lo]), e.bottom_cap = true;
  if (top_tip) e.top = ring_height(path[hi]), e.top_cap = true;
  if (!(e.top - e.bottom > 100 * same_height)) return std::nullopt;
  // The end whose outline the others scale: one with a cap (or a dome), the larger.
  const int ref = e.top_cap != e.bottom_cap
                      ? (e.top_cap ? path[hi] : path[lo])
                      : (ring_area[path[hi]] >= ring_area[path[lo]] ? path[hi] : path[lo]);
  bool scaled = false;
  for (int k = lo; k <= hi; ++k) {
    const double s = scale[path[k]] / scale[ref];
    if (!(s >= kLeastLoftScale && s <= 1 / kLeastLoftScale)) return std::nullopt;
    scaled = scaled || std::abs(s - 1) > 1e-9;
  }
  if (!scaled && (e.top_cap || e.bottom_cap)) return std::nullopt;  // an extrusion's business
  // A dome's cap: its outline's area (its projection along the axis).
  for (int k : {lo, hi})
    if (k != 0 && k != nr - 1) cap_area[path[k]] = ring_area[path[k]];
  if (e.top_cap && e.bottom_cap) {  // the same outline, scaled
    const int other = ref == path[hi] ? path[lo] : path[hi];
    const double s = scale[other] / scale[ref];
    if (std::abs(cap_area[other] - s * s * cap_area[ref]) > 1e-3 * cap_area[ref])
      return std::nullopt;
  }
  for (int k = lo; k <= hi; ++k)
    e.profile.push_back({ring_height(path[k]), scale[path[k]] / scale[ref]});
  // The domes' profiles, from the wall's end ring to the pole, and their triangles (wall
  // triangles and flat steps between rings of the dome).
  std::vector<int> position(nr);
  for (int k = 0; k < nr; ++k) position[path[k]] = k;
  const auto dome_profile = [&](int from, int to) {
    std::vector<std::array<double, 2>> d;
    for (int k = from;; k += to > from ? 1 : -1) {
      d.push_back({ring_height(path[k]), scale[path[k]] / scale[ref]});
      if (k == to) break;
    }
    if (d.back()[1] > 0) d.push_back({d.back()[0], 0.0});  // a flat cap, to the axis
    return d;
  };
  std::vector<std::array<double, 2>> bottom_dome, top_dome;
  if (lo > 0) bottom_dome = dome_profile(lo, 0);
  if (hi < nr - 1) top_dome = dome_profile(hi, nr - 1);
  const bool ref_on_top = ref == path[hi];
  e.cap_dome = ref_on_top ? top_dome : bottom_dome;
  e.other_dome = ref_on_top ? bottom_dome : top_dome;
  e.outline = outline;
  e.across = u;
  e.outline_scale = scale[ref];
  e.centre = centroid.x() * u + centroid.y() * v;
  e.radius = 0;
  for (int i : rings[ref]) e.radius += (flat2(i) - centroid).norm() / rings[ref].size();
  e.cap_on_top = ref_on_top;
  if (!e.cap_dome.empty()) {
    // The dome's triangles moved along the axis onto the plane of the ring round it.
    std::vector<int> dome;
    for (int t = 0; t < nt; ++t) {
      int least = nr, most = -1;
      bool on_rings = true;
      for (int i : mesh.triangles[t]) {
        if (ring_of[i] < 0) {
          on_rings = false;
          break;
        }
        least = std::min(least, position[ring_of[i]]);
        most = std::max(most, position[ring_of[i]]);
      }
      if (on_rings && (ref_on_top ? least >= hi : most <= lo)) dome.push_back(t);
    }
    // A flat cap at the tip (its inner vertices on no ring).
    if (const int end = ref_on_top ? path.back() : path.front(); caps.contains(end)) {
      const std::size_t walls = dome.size();  // sorted
      for (int t : caps.at(end))
        if (!std::binary_search(dome.begin(), dome.begin() + walls, t)) dome.push_back(t);
      std::sort(dome.begin(), dome.end());
    }
    e.cap = sub_mesh(mesh, dome);
    const double at = ring_height(ref);
    for (Vec3& p : e.cap.vertices) p -= (p.dot(axis) - at) * axis;
    e.cap_area = ring_area[ref];
    e.cap_facing = facing_of(e.cap);
  } else if (caps.contains(ref)) {
    e.cap = sub_mesh(mesh, caps.at(ref));
    e.cap_area = cap_area.at(ref);
    e.cap_facing = facing_of(e.cap);
  } else {
    // Open at both ends: the rim fanned round the axis, for its border.
    e.cap_made = true;
    const std::vector<int>& rim = rings[ref];
    const int m = static_cast<int>(rim.size());
    for (int i : rim) e.cap.vertices.push_back(mesh.vertices[i]);
    e.cap.vertices.push_back(e.centre + ring_height(ref) * axis);
    for (int i = 0; i < m; ++i) e.cap.triangles.push_back({m, i, (i + 1) % m});
    // Facing as a cap glued to the wall would: across the rim's first edge the wall's
    // triangle runs it the other way.
    bool forward = false;
    for (int t : wall)
      for (int k = 0; k < 3; ++k)
        if (mesh.triangles[t][k] == rim[0] && mesh.triangles[t][(k + 1) % 3] == rim[1])
          forward = true;
    const Vec3 fan = facing_of(e.cap);
    e.cap_facing = forward ? Vec3(-fan) : fan;
    e.cap_area = ring_area[ref];
  }
  return e;
}

/// \p p (a point in the plane across \p e's axis at the height where \p dome starts) lifted
/// along the axis onto \p dome (e.cap_dome or e.other_dome), by its scale: its distance from the
/// axis over that of the outline (\p star, set to e.outline) in its direction. \p p itself
/// where the dome is empty.
Vec3 lifted(const Extrusion& e, const StarOutline& star,
            const std::vector<std::array<double, 2>>& dome, const Vec3& p) {
  if (dome.size() < 2) return p;
  const Vec3 off = p - e.centre, across = off - off.dot(e.axis) * e.axis;
  const Vec2 q(across.dot(e.across), across.dot(e.axis.cross(e.across)));
  double scale = 0;  // against the cap's end
  if (q.norm() > 0) {
    const double distance = star.at(q).second;
    if (distance > 0) scale = q.norm() / distance / e.outline_scale;
  }
  double height = dome.back()[0];
  if (scale >= dome.front()[1]) {
    height = dome.front()[0];
  } else {
    for (std::size_t k = 0; k + 1 < dome.size(); ++k)
      if (scale >= dome[k + 1][1]) {
        const double w = (dome[k][1] - scale) / (dome[k][1] - dome[k + 1][1]);
        height = dome[k][0] + w * (dome[k + 1][0] - dome[k][0]);
        break;
      }
  }
  return p + (height - dome.front()[0]) * e.axis;
}

}  // namespace

std::vector<RowBorder> row_borders(const Extrusion& e, double size) {
  std::vector<RowBorder> out;
  if (e.profile.empty()) {
    const int rows = std::max(1, static_cast<int>(std::lround((e.top - e.bottom) / size)));
    for (int j = 0; j <= rows; ++j) out.push_back({static_cast<double>(j) / rows, 1.0});
    return out;
  }
  // The profile from the cap's end, each corner as (height, scale times the radius).
  std::vector<Vec2> p;
  for (const auto& [h, s] : e.profile) p.push_back(Vec2(h, s * e.radius));
  if (e.cap_on_top) std::reverse(p.begin(), p.end());
  const double from = p.front().x(), to = p.back().x();
  const auto border_at = [&](const Vec2& q) {
    return RowBorder{(q.x() - from) / (to - from), q.y() / e.radius};
  };
  out.push_back(border_at(p.front()));
  const int m = static_cast<int>(p.size());
  for (int start = 0; start + 1 < m;) {
    int end = start + 1;  // the run from start to end: no corner inside
    while (end + 1 < m) {
      const Vec2 a = p[end] - p[end - 1], b = p[end + 1] - p[end];
      if (std::atan2(std::abs(cross2(a, b)), a.dot(b)) > kProfileCorner) break;
      ++end;
    }
    double length = 0;
    for (int k = start; k < end; ++k) length += (p[k + 1] - p[k]).norm();
    const int rows = std::max(1, static_cast<int>(std::lround(length / size)));
    int k = start;
    double before = 0;  // length of the run up to corner k
    for (int i = 1; i < rows; ++i) {
      const double at = length * i / rows;
      while (k + 1 < end && before + (p[k + 1] - p[k]).norm() < at)
        before += (p[k + 1] - p[k]).norm(), ++k;
      const double segment = (p[k + 1] - p[k]).norm();
      const double w = segment > 0 ? std::clamp((at - before) / segment, 0.0, 1.0) : 0.0;
      out.push_back(border_at(p[k] + w * (p[k + 1] - p[k])));
    }
    out.push_back(border_at(p[end]));
    start = end;
  }
  return out;
}

std::optional<Extrusion> find_extrusion(const TriangleMesh& mesh) {
  const int nt = static_cast<int>(mesh.triangles.size());
  if (nt < 4) return std::nullopt;
  std::vector<Vec3> normals(nt);
  std::vector<double> areas(nt);
  const BoundingBox box = bounding_box(mesh);
  if (!(box.min.allFinite() && box.max.allFinite())) return std::nullopt;
  const double same_height = kSameHeight * box.diagonal();
  // Candidate axes: the directions the most area faces (either way), a cap's among them.
  struct KeyHash {
    std::size_t operator()(const std::array<long long, 3>& k) const {
      return std::hash<long long>()(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
    }
  };
  std::unordered_map<std::array<long long, 3>, std::pair<double, Vec3>, KeyHash> by_direction;
  std::map<std::array<long long, 3>, int> triangles_by_direction;
  for (int t = 0; t < nt; ++t) {
    const auto& tr = mesh.triangles[t];
    const Vec3 c = (mesh.vertices[tr[1]] - mesh.vertices[tr[0]])
                       .cross(mesh.vertices[tr[2]] - mesh.vertices[tr[0]]);
    areas[t] = 0.5 * c.norm();
    if (!(areas[t] > 0)) return std::nullopt;
    normals[t] = c.normalized();
    Vec3 n = normals[t];
    for (int k = 0; k < 3; ++k)  // one sign for both ways
      if (std::abs(n[k]) > 1e-9) {
        if (n[k] < 0) n = -n;
        break;
      }
    const std::array<long long, 3> key = {std::llround(n.x() * 1e3), std::llround(n.y() * 1e3),
                                          std::llround(n.z() * 1e3)};
    auto& [area, dir] = by_direction[key];
    if (area == 0) dir = n;
    area += areas[t];
    ++triangles_by_direction[key];
  }
  // Most area first; equal areas (a cube's faces) in the order of their directions' keys, so
  // that the axis taken never depends on the hash table's order.
  std::vector<std::tuple<double, std::array<long long, 3>, Vec3>> candidates;
  for (const auto& [key, entry] : by_direction)
    candidates.emplace_back(entry.first, key, entry.second);
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
    if (std::get<0>(a) != std::get<0>(b)) return std::get<0>(a) > std::get<0>(b);
    return std::get<1>(a) < std::get<1>(b);
  });
  if (candidates.size() > 4) candidates.resize(4);
  std::optional<std::map<std::pair<int, int>, int>> uses;
  std::optional<Extrusion> best;
  for (const auto& [area, key, dir] : candidates) {
    std::optional<Extrusion> e = extrusion_along(mesh, dir, normals, areas, same_height, uses);
    if (e && (!best || e->cap_area > best->cap_area)) best = std::move(e);
  }
  if (best) return best;
  // A loft: along a cap's normal, or (open at both ends) a rim's.
  if (!uses) uses = edge_uses(mesh);
  std::vector<Vec3> axes;
  for (const auto& [area, key, dir] : candidates) axes.push_back(dir);
  std::vector<std::vector<int>> loops = loops_of(border_edges(mesh));
  std::sort(loops.begin(), loops.end(),
            [](const auto& a, const auto& b) { return a.size() > b.size(); });
  if (loops.size() > 4) loops.resize(4);  // a scan's many holes: the longest rims only
  for (const std::vector<int>& loop : loops) {
    std::vector<Vec3> corners;
    for (int i : loop) corners.push_back(mesh.vertices[i]);
    const Vec3 normal = area_vector(corners);
    if (normal.norm() > 0) axes.push_back(normal.normalized());
  }
  // Or (closed, a pole at an end: a capsule, a UV sphere) the way the fan round the vertex of
  // most triangles faces, where it has at least kPoleFan.
  {
    constexpr int kPoleFan = 8;
    std::vector<int> fan(mesh.vertices.size(), 0);
    for (const auto& tr : mesh.triangles)
      for (int i : tr) ++fan[i];
    const auto most = std::max_element(fan.begin(), fan.end());
    if (most != fan.end() && *most >= kPoleFan) {
      const int pole = static_cast<int>(most - fan.begin());
      Vec3 facing = Vec3::Zero();
      for (int t = 0; t < nt; ++t)
        for (int i : mesh.triangles[t])
          if (i == pole) facing += areas[t] * normals[t];
      if (facing.norm() > 0) axes.push_back(facing.normalized());
    }
  }
  // Or the way the most triangles face, where at least kFlatFan do: a flat polygon of many
  // sides fanned from one of its corners (a sphere's pole as OpenSCAD writes it, a few
  // degrees across: too small for the directions of most area).
  {
    constexpr int kFlatFan = 8;
    const auto most =
        std::max_element(triangles_by_direction.begin(), triangles_by_direction.end(),
                         [](const auto& a, const auto& b) { return a.second < b.second; });
    if (most != triangles_by_direction.end() && most->second >= kFlatFan)
      axes.push_back(by_direction.at(most->first).second);
  }
  for (const Vec3& axis : axes) {
    std::optional<Extrusion> e = loft_along(mesh, axis, normals, areas, same_height, *uses);
    if (e && (!best || e->cap_area > best->cap_area)) best = std::move(e);
  }
  return best;
}

PolyMesh sweep_extrusion(const PolyMesh& cap, const Extrusion& e,
                         const std::vector<RowBorder>& borders,
                         std::vector<std::array<int, 2>>* along_rims,
                         std::vector<std::array<int, 2>>* along_axis) {
  PolyMesh out;
  const int rows = static_cast<int>(borders.size()) - 1;
  if (rows < 1 || cap.n_faces() == 0) return out;
  const double from = e.cap_on_top ? e.top : e.bottom, to = e.cap_on_top ? e.bottom : e.top;
  const Vec3 d = (to - from) * e.axis;
  // Row j's copy of a point p of the cap: moved borders[j].way of d, and (a loft) its offset
  // from the axis scaled (by exactly 1 along an extrusion: p moved alone).
  const auto in_row = [&](const Vec3& p, int j) {
    const Vec3 off = p - e.centre, across = off - off.dot(e.axis) * e.axis;
    return Vec3(p + borders[j].way * d + (borders[j].scale - 1.0) * across);
  };
  const bool other_cap = e.cap_on_top ? e.bottom_cap : e.top_cap;
  // A dome's cap lifted onto it (lifted()).
  StarOutline star;
  if ((!e.cap_dome.empty() || !e.other_dome.empty()) && !star.set(e.outline)) return out;
  using VH = OpenMesh::VertexHandle;
  // The faces below are made as if the cap's quads faced the way its triangles in the target
  // do (out of the solid, or in where the target's triangles face in); where they face the
  // other way, each is turned.
  Vec3 facing = Vec3::Zero();  // the sum of the quads' area vectors
  for (auto f : cap.faces()) {
    std::vector<Vec3> p;
    for (auto v : cap.fv_range(f)) p.push_back(to_eigen(cap.point(v)));
    facing += area_vector(p);
  }
  const bool inward = facing.dot(e.cap_facing) < 0;
  const int n = static_cast<int>(cap.n_vertices());
  // Row j of the cap's vertices, moved by j / rows of the way: the border in every row, the
  // inner vertices in the first and (a cap there) the last.
  std::vector<std::vector<VH>> at(rows + 1, std::vector<VH>(n));
  for (auto v : cap.vertices()) {
    const Vec3 p = to_eigen(cap.point(v));
    if (cap.is_boundary(v) || !e.cap_made)
      at[0][v.idx()] = out.add_vertex(to_openmesh(lifted(e, star, e.cap_dome, p)));
    for (int j = 1; j <= rows; ++j)
      if (cap.is_boundary(v) || (j == rows && other_cap))
        at[j][v.idx()] = out.add_vertex(
            to_openmesh(j == rows ? lifted(e, star, e.other_dome, in_row(p, j)) : in_row(p, j)));
  }
  const auto add = [&](std::vector<VH> corners, bool turned) {
    if (turned != inward) std::reverse(corners.begin(), corners.end());
    return out.add_face(corners).is_valid();
  };
  // The cap in row \p row, turned there (the other end's copy faces the other way).
  const auto add_cap = [&](int row, bool turned) {
    for (auto f : cap.faces()) {
      std::vector<VH> corners;
      for (auto v : cap.fv_range(f)) corners.push_back(at[row][v.idx()]);
      if (!add(corners, turned)) return false;
    }
    return true;
  };
  if (!e.cap_made && !add_cap(0, false)) return PolyMesh();
  // A border halfedge u -> v of the cap (no face on it; the cap's face runs v -> u) starts a
  // column of the wall, each of its quads running u -> v along its upper rim.
  for (auto h : cap.halfedges()) {
    if (!cap.is_boundary(h)) continue;
    const int u = cap.from_vertex_handle(h).idx(), v = cap.to_vertex_handle(h).idx();
    for (int j = 0; j < rows; ++j)
      if (!add({at[j][u], at[j][v], at[j + 1][v], at[j + 1][u]}, false)) return PolyMesh();
    if (along_rims)
      for (int j = 1; j < rows; ++j) along_rims->push_back({at[j][u].idx(), at[j][v].idx()});
    if (along_axis)
      for (int j = 0; j < rows; ++j) along_axis->push_back({at[j][u].idx(), at[j + 1][u].idx()});
  }
  if (other_cap && !add_cap(rows, true)) return PolyMesh();
  return out;
}

}  // namespace kerfab::quads
