#include "kerfab/adapters/polygon_ops.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <polyclipping/clipper.hpp>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

namespace kerfab {
namespace {

constexpr double kScale = 1e5;  // 10 nm per unit

struct PointHash {
  std::size_t operator()(const ClipperLib::IntPoint& p) const {
    return std::hash<std::uint64_t>()(static_cast<std::uint64_t>(p.X) * 0x9E3779B97F4A7C15ULL ^
                                      static_cast<std::uint64_t>(p.Y));
  }
};

ClipperLib::Path to_path(const Polygon2& p) {
  ClipperLib::Path out;
  out.reserve(p.size());
  for (const auto& v : p)
    out.emplace_back(static_cast<ClipperLib::cInt>(std::llround(v.x() * kScale)),
                     static_cast<ClipperLib::cInt>(std::llround(v.y() * kScale)));
  return out;
}

/// \p ring with a vertex inserted wherever one of its vertices touches the inside of one of its
/// edges, the way Clipper's scan line sees a touch: the edge's x at the vertex's y, rounded to
/// the grid, is the vertex's x. A sweep in y keeps the edges spanning the current y.
ClipperLib::Path with_touch_points(const ClipperLib::Path& ring) {
  const std::size_t n = ring.size();
  if (n < 4) return ring;
  std::vector<std::size_t> by_low(n), by_y(n);  // edges by their lower y, vertices by y
  for (std::size_t i = 0; i < n; ++i) by_low[i] = by_y[i] = i;
  auto low = [&](std::size_t e) { return std::min(ring[e].Y, ring[(e + 1) % n].Y); };
  auto high = [&](std::size_t e) { return std::max(ring[e].Y, ring[(e + 1) % n].Y); };
  std::sort(by_low.begin(), by_low.end(), [&](auto a, auto b) { return low(a) < low(b); });
  std::sort(by_y.begin(), by_y.end(), [&](auto a, auto b) { return ring[a].Y < ring[b].Y; });
  std::vector<std::size_t> active;
  std::vector<std::pair<std::size_t, std::size_t>> touches;  // (edge, vertex)
  std::size_t next = 0;
  for (std::size_t v : by_y) {
    const ClipperLib::IntPoint& p = ring[v];
    while (next < n && low(by_low[next]) <= p.Y) active.push_back(by_low[next++]);
    std::erase_if(active, [&](std::size_t e) { return high(e) < p.Y; });
    for (std::size_t e : active) {
      const ClipperLib::IntPoint &a = ring[e], &b = ring[(e + 1) % n];
      if (a == p || b == p) continue;  // its own edges, or a repeated point (split later)
      bool touch;
      if (a.Y == b.Y) {
        touch = p.Y == a.Y && std::min(a.X, b.X) < p.X && p.X < std::max(a.X, b.X);
      } else {
        const ClipperLib::IntPoint& bot = a.Y > b.Y ? a : b;
        const ClipperLib::IntPoint& top = a.Y > b.Y ? b : a;
        if (!(top.Y < p.Y && p.Y < bot.Y)) continue;
        const double dx = static_cast<double>(top.X - bot.X) / static_cast<double>(top.Y - bot.Y);
        touch = bot.X + std::llround(dx * static_cast<double>(p.Y - bot.Y)) == p.X;
      }
      if (touch) touches.emplace_back(e, v);
    }
  }
  if (touches.empty()) return ring;
  // Inserted in order along each edge.
  auto along = [&](const std::pair<std::size_t, std::size_t>& t) {
    const ClipperLib::IntPoint &a = ring[t.first], &p = ring[t.second];
    return std::abs(static_cast<double>(p.X - a.X)) + std::abs(static_cast<double>(p.Y - a.Y));
  };
  std::sort(touches.begin(), touches.end(), [&](const auto& s, const auto& t) {
    return s.first != t.first ? s.first < t.first : along(s) < along(t);
  });
  ClipperLib::Path out;
  out.reserve(n + touches.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back(ring[i]);
    for (; k < touches.size() && touches[k].first == i; ++k) out.push_back(ring[touches[k].second]);
  }
  return out;
}

/// Every ring of \p paths that passes through one point twice, split there into the loops it
/// is made of, so that no ring touches itself (what Clipper's StrictlySimple does, but in
/// linear time: Clipper compares every pair of points of a ring, which made the Booleans of
/// parts with thousands of vertices quadratic). Each loop keeps its direction, so a pinched-off
/// lobe stays an outer ring and a hole touching its outer ring at a vertex becomes a hole.
ClipperLib::Paths split_at_repeated_points(ClipperLib::Paths paths) {
  ClipperLib::Paths out;
  out.reserve(paths.size());
  std::unordered_map<ClipperLib::IntPoint, std::size_t, PointHash> at;  // point -> place on `stack`
  ClipperLib::Path stack;
  for (auto& given : paths) {
    ClipperLib::Path path = with_touch_points(given);
    at.clear();
    stack.clear();
    for (const auto& p : path) {
      const auto [it, fresh] = at.try_emplace(p, stack.size());
      if (fresh) {
        stack.push_back(p);
        continue;
      }
      // The loop from the first visit of p to here closes: cut it out, p stays on the stack.
      const std::size_t first = it->second;
      ClipperLib::Path loop(stack.begin() + static_cast<std::ptrdiff_t>(first), stack.end());
      for (std::size_t i = first + 1; i < stack.size(); ++i) at.erase(stack[i]);
      stack.resize(first + 1);
      out.push_back(std::move(loop));
    }
    if (stack.size() < path.size())
      out.push_back(stack);
    else
      out.push_back(std::move(path));
  }
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

/// Closed paths with their bounding boxes, for winding numbers that skip the paths a point's
/// rightward ray cannot cross. Asked about many points (\p indexed), a long path also sorts its
/// edges into bands of y, so that a point looks only at the edges of its band: a part's outline
/// less its opening asks once or twice per piece of the result, hundreds of pieces at teeth.
class Region {
 public:
  Region(const ClipperLib::Paths& paths, bool indexed) : paths_(paths) {
    box_.reserve(paths.size());
    bands_.resize(paths.size());
    for (std::size_t k = 0; k < paths.size(); ++k) {
      const auto& path = paths[k];
      constexpr double inf = std::numeric_limits<double>::infinity();
      Box b{inf, -inf, -inf};  // min y, max x, max y
      for (const auto& q : path) {
        b.max_x = std::max(b.max_x, static_cast<double>(q.X));
        b.min_y = std::min(b.min_y, static_cast<double>(q.Y));
        b.max_y = std::max(b.max_y, static_cast<double>(q.Y));
      }
      box_.push_back(b);
      if (indexed && path.size() >= kIndexedEdges) index(k);
    }
  }
  /// Winding number of the paths around (x, y) [grid units].
  int winding(double x, double y) const {
    int w = 0;
    for (std::size_t k = 0; k < paths_.size(); ++k) {
      const Box& b = box_[k];
      if (x > b.max_x || y < b.min_y || y > b.max_y) continue;
      const auto& path = paths_[k];
      const std::size_t n = path.size();
      auto count = [&](std::size_t i) {
        const auto &a = path[i], &c = path[(i + 1) % n];
        const double ay = static_cast<double>(a.Y), cy = static_cast<double>(c.Y);
        if ((ay <= y) == (cy <= y)) return;
        const double ax = static_cast<double>(a.X), cx = static_cast<double>(c.X);
        const double cross = (cx - ax) * (y - ay) - (cy - ay) * (x - ax);
        if (cy > ay && cross > 0) ++w;
        if (cy < ay && cross < 0) --w;
      };
      const Bands& bands = bands_[k];
      if (bands.start.empty()) {
        for (std::size_t i = 0; i < n; ++i) count(i);
      } else {
        const std::size_t band = bands.of(y);
        for (std::size_t e = bands.start[band]; e < bands.start[band + 1]; ++e)
          count(bands.edges[e]);
      }
    }
    return w;
  }

 private:
  static constexpr std::size_t kIndexedEdges = 64;
  struct Box {
    double min_y, max_x, max_y;
  };
  /// A path's edges by bands of equal height in y: band j holds every edge whose y range
  /// [min, max] meets it (edges[start[j]], ..., edges[start[j + 1] - 1]). An edge crossing the
  /// horizontal at y has min <= y < max, so it is in the band of y.
  struct Bands {
    double min_y = 0, height = 1;
    std::vector<std::size_t> start, edges;
    std::size_t of(double y) const {
      const double j = std::floor((y - min_y) / height);
      return static_cast<std::size_t>(std::clamp(j, 0.0, static_cast<double>(start.size() - 2)));
    }
  };
  void index(std::size_t k) {
    const auto& path = paths_[k];
    const std::size_t n = path.size();
    const Box& b = box_[k];
    if (!(b.max_y > b.min_y)) return;
    Bands bands;
    const std::size_t count = std::max<std::size_t>(1, n / 8);
    bands.min_y = b.min_y;
    bands.height = (b.max_y - b.min_y) / static_cast<double>(count);
    bands.start.assign(count + 1, 0);
    auto span = [&](std::size_t i) {
      const double ay = static_cast<double>(path[i].Y);
      const double cy = static_cast<double>(path[(i + 1) % n].Y);
      return std::pair{bands.of(std::min(ay, cy)), bands.of(std::max(ay, cy))};
    };
    std::size_t total = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const auto [lo, hi] = span(i);
      total += hi - lo + 1;
      for (std::size_t j = lo; j <= hi; ++j) ++bands.start[j + 1];
    }
    // Long edges across most bands (a tall, thin path) gain nothing: the plain scan is kept.
    if (total > 8 * n) return;
    for (std::size_t j = 0; j < count; ++j) bands.start[j + 1] += bands.start[j];
    bands.edges.resize(total);
    std::vector<std::size_t> at(bands.start.begin(), bands.start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      const auto [lo, hi] = span(i);
      for (std::size_t j = lo; j <= hi; ++j) bands.edges[at[j]++] = i;
    }
    bands_[k] = std::move(bands);
  }
  const ClipperLib::Paths& paths_;
  std::vector<Box> box_;
  std::vector<Bands> bands_;  // per path; empty: scanned whole
};

/// Clipper 1 can hand back a ring with the wrong direction where touching corners abound (an
/// island of material alone in a hole came back clockwise, as a hole; tests/polygon_ops_test).
/// Each ring is checked against the fill rule on the inputs: just left of its longest edge must
/// be inside the result; if only the right side is, the ring is turned round.
void orient_by_fill(ClipperLib::Paths& rings, const std::function<bool(double, double)>& inside) {
  for (auto& ring : rings) {
    const std::size_t n = ring.size();
    if (n < 3) continue;
    std::size_t longest = 0;
    double best = -1;
    for (std::size_t i = 0; i < n; ++i) {
      const double dx = static_cast<double>(ring[(i + 1) % n].X - ring[i].X);
      const double dy = static_cast<double>(ring[(i + 1) % n].Y - ring[i].Y);
      if (dx * dx + dy * dy > best) best = dx * dx + dy * dy, longest = i;
    }
    const auto &a = ring[longest], &b = ring[(longest + 1) % n];
    const double len = std::sqrt(best);
    if (len < 20) continue;  // a speck of rounding debris: CleanPolygons' business
    // 2 grid units off the edge: beyond the half unit by which Clipper rounds its vertices.
    const double mx = 0.5 * static_cast<double>(a.X + b.X);
    const double my = 0.5 * static_cast<double>(a.Y + b.Y);
    const double nx = -static_cast<double>(b.Y - a.Y) / len * 2;
    const double ny = static_cast<double>(b.X - a.X) / len * 2;
    if (!inside(mx + nx, my + ny) && inside(mx - nx, my - ny))
      std::reverse(ring.begin(), ring.end());
  }
}

/// Clipper 1 can return a spike of an outer ring together with a hole of exactly the spike's
/// triangle: the two cancel, but a caller that keeps the outer ring alone (every part outline)
/// keeps the spike as material. Seen where a cut-back's corner wedge, its tip on the outline,
/// shares its sides with the cut-backs on both sides of it: a 0.15 mm wide, 1.6 mm long hair
/// beside a slit of 0.06 mm in the demo's sheet (tests/polygon_ops_test). Where a hole shares a
/// vertex with an outer ring, the rings united once more by their winding numbers come out
/// clean; a hole that truly touches its outer ring at a point stays a hole.
ClipperLib::Paths without_cancelling_holes(ClipperLib::Paths rings) {
  // Every Boolean passes here: the rings are looked at, not copied, and most results have no
  // hole at all.
  std::vector<bool> outer(rings.size());
  bool any_hole = false;
  for (std::size_t i = 0; i < rings.size(); ++i)
    any_hole = !(outer[i] = ClipperLib::Orientation(rings[i])) || any_hole;
  if (!any_hole) return rings;
  std::unordered_set<ClipperLib::IntPoint, PointHash> on_outer;
  for (std::size_t i = 0; i < rings.size(); ++i)
    if (outer[i]) on_outer.insert(rings[i].begin(), rings[i].end());
  bool shared = false;
  for (std::size_t i = 0; i < rings.size() && !shared; ++i)
    if (!outer[i])
      shared = std::any_of(rings[i].begin(), rings[i].end(),
                           [&](const ClipperLib::IntPoint& p) { return on_outer.contains(p); });
  if (!shared) return rings;
  // The rings as they are, filled by their winding numbers: outer rings count +1, holes -1 (an
  // island in a hole is +1 again).
  ClipperLib::Clipper c;
  c.AddPaths(rings, ClipperLib::ptSubject, true);
  ClipperLib::Paths out;
  c.Execute(ClipperLib::ctUnion, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return out;
}

enum class Op { kIntersection, kUnion, kDifference };

/// One Boolean of \p subject and \p clip (non-zero fill), strictly simple and oriented.
std::vector<Polygon2> boolean(Op op, const ClipperLib::Paths& subject,
                              const ClipperLib::Paths& clip) {
  ClipperLib::Clipper c;
  c.AddPaths(subject, ClipperLib::ptSubject, true);
  if (!clip.empty()) c.AddPaths(clip, ClipperLib::ptClip, true);
  ClipperLib::Paths out;
  const ClipperLib::ClipType type = op == Op::kIntersection ? ClipperLib::ctIntersection
                                    : op == Op::kUnion      ? ClipperLib::ctUnion
                                                            : ClipperLib::ctDifference;
  c.Execute(type, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  out = without_cancelling_holes(std::move(out));
  out = split_at_repeated_points(std::move(out));
  // Two winding numbers per ring of the result: worth indexing the inputs' edges for many.
  const bool indexed = out.size() >= 4;
  const Region in_s(subject, indexed), in_c(clip, indexed);
  orient_by_fill(out, [&](double x, double y) {
    const bool in_subject = in_s.winding(x, y) != 0;
    switch (op) {
      case Op::kIntersection: return in_subject && in_c.winding(x, y) != 0;
      case Op::kUnion: return in_subject;
      case Op::kDifference: return in_subject && in_c.winding(x, y) == 0;
    }
    return false;
  });
  return from_paths(std::move(out));
}

/// True when the bounding boxes of \p a and \p b (grid units) have no point in common.
bool boxes_apart(const ClipperLib::Path& a, const ClipperLib::Path& b) {
  if (a.empty() || b.empty()) return true;
  auto box = [](const ClipperLib::Path& p) {
    std::array<ClipperLib::cInt, 4> r = {p[0].X, p[0].Y, p[0].X, p[0].Y};  // min x, y, max x, y
    for (const auto& q : p) {
      r[0] = std::min(r[0], q.X), r[1] = std::min(r[1], q.Y);
      r[2] = std::max(r[2], q.X), r[3] = std::max(r[3], q.Y);
    }
    return r;
  };
  const auto p = box(a), q = box(b);
  return p[2] < q[0] || q[2] < p[0] || p[3] < q[1] || q[3] < p[1];
}

ClipperLib::Paths to_paths(const std::vector<Polygon2>& polygons) {
  ClipperLib::Paths out;
  out.reserve(polygons.size());
  for (const auto& p : polygons) out.push_back(to_path(p));
  return out;
}

}  // namespace

std::vector<Polygon2> polygon_intersection(const Polygon2& a, const Polygon2& b) {
  ClipperLib::Path pa = to_path(a), pb = to_path(b);
  // Most calls (two thirds on the demo) pair polygons that are far apart: boxes apart on the
  // grid, no area in common, the empty result Clipper would return.
  if (boxes_apart(pa, pb)) return {};
  return boolean(Op::kIntersection, {std::move(pa)}, {std::move(pb)});
}

double common_area(const Polygon2& a, const Polygon2& b) {
  double area = 0;
  for (const Polygon2& c : polygon_intersection(a, b)) area += polygon_area(c);
  return area;
}

std::vector<Polygon2> polygon_union(const std::vector<Polygon2>& polygons) {
  return boolean(Op::kUnion, to_paths(polygons), {});
}

std::vector<Polygon2> polygon_difference(const std::vector<Polygon2>& a,
                                         const std::vector<Polygon2>& b) {
  return boolean(Op::kDifference, to_paths(a), to_paths(b));
}

std::vector<Polygon2> polygon_offset(const std::vector<Polygon2>& polygons, double delta) {
  ClipperLib::ClipperOffset o(4.0);
  for (const auto& p : polygons)
    o.AddPath(to_path(p), ClipperLib::jtMiter, ClipperLib::etClosedPolygon);
  ClipperLib::Paths out;
  o.Execute(out, delta * kScale);
  return from_paths(out);
}

std::vector<Polygon2> polygon_offset_round(const std::vector<Polygon2>& polygons, double delta,
                                           double tolerance) {
  ClipperLib::ClipperOffset o(4.0, std::max(tolerance, 1.0 / kScale) * kScale);
  for (const auto& p : polygons)
    o.AddPath(to_path(p), ClipperLib::jtRound, ClipperLib::etClosedPolygon);
  ClipperLib::Paths out;
  o.Execute(out, delta * kScale);
  return from_paths(out);
}

}  // namespace kerfab
