#include "kerfab/eval/surface_distance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <queue>

#include "kerfab/adapters/target_surface.h"
#include "kerfab/core/errors.h"
#include "kerfab/core/parallel.h"

namespace kerfab {
namespace {

/// A triangle cut into cells no wider than a spacing in any direction, whatever its shape: its
/// longest edge is the base; lines parallel to it cut it into bands no higher than the spacing,
/// and each band is cut into trapezoids no wider than the spacing at equal fractions of its two
/// sides. A sliver (a ruling strip's triangles are often 50 times longer than wide) thus gets
/// cells in proportion to its area, where a grid on its edges would give the square of its
/// length over the spacing.
struct TriangleCells {
  Vec3 apex, base0, base1;
  int bands = 1;
  double base = 0;  ///< longest edge [mm]
  TriangleCells(const Vec3& a, const Vec3& b, const Vec3& c, double spacing) {
    const std::array<Vec3, 3> p = {a, b, c};
    int k = 0;  // the longest edge runs from p[k] to p[k + 1]
    for (int i = 1; i < 3; ++i)
      if ((p[(i + 1) % 3] - p[i]).norm() > (p[(k + 1) % 3] - p[k]).norm()) k = i;
    base0 = p[k];
    base1 = p[(k + 1) % 3];
    apex = p[(k + 2) % 3];
    base = (base1 - base0).norm();
    const double height = base > 0 ? (base1 - base0).cross(apex - base0).norm() / base : 0.0;
    bands = std::max(1, static_cast<int>(std::ceil(height / spacing)));
    spacing_ = spacing;
  }
  /// Cells of band \p k (0 at the base).
  int cells(int k) const {
    return std::max(1, static_cast<int>(std::ceil(base * (1.0 - double(k) / bands) / spacing_)));
  }
  long count() const {
    long n = 0;
    for (int k = 0; k < bands; ++k) n += cells(k);
    return n;
  }
  /// Calls \p f(centroid, area) for every cell.
  template <class F>
  void for_each(F&& f) const {
    for (int k = 0; k < bands; ++k) {
      const double u0 = double(k) / bands, u1 = double(k + 1) / bands;
      const Vec3 l0 = base0 + u0 * (apex - base0), l1 = base1 + u0 * (apex - base1);
      const Vec3 h0 = base0 + u1 * (apex - base0), h1 = base1 + u1 * (apex - base1);
      const int n = cells(k);
      for (int j = 0; j < n; ++j) {
        const double s0 = double(j) / n, s1 = double(j + 1) / n;
        const Vec3 p00 = l0 + s0 * (l1 - l0), p01 = l0 + s1 * (l1 - l0);
        const Vec3 p10 = h0 + s0 * (h1 - h0), p11 = h0 + s1 * (h1 - h0);
        // The trapezoid as two triangles: its area and area-weighted centroid.
        const double a1 = 0.5 * (p01 - p00).cross(p11 - p00).norm();
        const double a2 = 0.5 * (p11 - p00).cross(p10 - p00).norm();
        const double area = a1 + a2;
        if (!(area > 0)) continue;
        const Vec3 centroid = (a1 * (p00 + p01 + p11) + a2 * (p00 + p11 + p10)) / (3.0 * area);
        f(centroid, area);
      }
    }
  }

 private:
  double spacing_ = 1;
};

int worker_count() { return std::min(8, hardware_threads()); }

struct Mean {
  double weighted_sum = 0, area = 0;
  long samples = 0;
  double value() const { return area > 0 ? weighted_sum / area : 0; }
};

/// Area-weighted mean distance from \p from to \p to: each triangle cut into cells no wider
/// than \p spacing (TriangleCells), each weighted by its area at its centroid.
Mean mean_distance(const TriangleMesh& from, const TargetSurface& to, double spacing) {
  const int threads = worker_count();
  std::vector<Mean> parts(threads);
  const int nt = static_cast<int>(from.triangles.size());
  run_parallel(threads, [&](int id) {
    Mean& r = parts[id];
    for (int ti = id; ti < nt; ti += threads) {
      const auto& t = from.triangles[ti];
      TriangleCells(from.vertices[t[0]], from.vertices[t[1]], from.vertices[t[2]], spacing)
          .for_each([&](const Vec3& x, double area) {
            r.weighted_sum += area * to.closest(x).distance;
            r.area += area;
            ++r.samples;
          });
    }
  });
  Mean total;
  for (const Mean& p : parts) {
    total.weighted_sum += p.weighted_sum;
    total.area += p.area;
    total.samples += p.samples;
  }
  return total;
}

/// Distance from \p p to the triangle (a, b, c): the nearest of its face, edges and corners,
/// told apart by the barycentric signs of p's projection.
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();  // corner a
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();  // corner b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();  // edge ab
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();  // corner c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)  // edge bc
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1 / (va + vb + vc);  // inside the face
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

/// The convex quad that triangles \p t1 and \p t2 of \p m make together, corners in order
/// (split by the diagonal from corner 0 to corner 2), when they share an edge, lie in one plane
/// and their union is convex; nothing otherwise.
std::optional<std::array<Vec3, 4>> convex_coplanar_pair(const TriangleMesh& m, int t1, int t2) {
  const auto &x = m.triangles[t1], &y = m.triangles[t2];
  for (int k = 0; k < 3; ++k) {
    const int a = x[k], b = x[(k + 1) % 3], c = x[(k + 2) % 3];  // shared edge a-b?
    int d = -1;
    for (int l = 0; l < 3; ++l)
      if (y[l] == b && y[(l + 1) % 3] == a) d = y[(l + 2) % 3];
    if (d < 0) continue;
    const Vec3 &pa = m.vertices[a], &pb = m.vertices[b], &pc = m.vertices[c],
               &pd = m.vertices[d];
    const Vec3 n1 = (pb - pa).cross(pc - pa), n2 = (pa - pb).cross(pd - pb);
    if (!(n1.norm() > 0 && n2.norm() > 0)) return std::nullopt;
    if (n1.normalized().dot(n2.normalized()) < 1 - 1e-12) return std::nullopt;
    // Convex: c and d on either side of the line a-b (true, the triangles do not overlap) and
    // a and b on either side of the line c-d.
    const Vec3 n = n1.normalized();
    const double sa = (pd - pc).cross(pa - pc).dot(n), sb = (pd - pc).cross(pb - pc).dot(n);
    if (sa * sb >= 0) return std::nullopt;
    return std::array<Vec3, 4>{pc, pa, pd, pb};  // c, a, d, b: diagonal c-d
  }
  return std::nullopt;
}

/// A triangle of the search: its corners, the distance at each and the triangle of the other
/// surface nearest each, and an upper bound on the distance anywhere on it.
struct Cell {
  std::array<Vec3, 3> p;
  std::array<double, 3> d;
  std::array<int, 3> near;
  double upper = 0;
  bool operator<(const Cell& o) const { return upper < o.upper; }
};

/// Bound on the distance to surface \p to over cell \p c, knowing also its centroid \p m
/// (distance \p dm, nearest triangle \p tm). Two bounds, the lower kept: (1) the distance to
/// a surface moves by at most the distance moved, and no point of the cell is farther from a
/// point than the farthest corner; (2) the distance to the surface is at most the distance to
/// any one of its triangles, which is convex, so over the cell at most its largest value at
/// a corner: tried for the triangles nearest the corners and the centroid. (2) is what keeps
/// cells where the surfaces run parallel from being cut without end. (3) The same for two of
/// those triangles that share an edge, lie in one plane and make a convex quad together (the
/// distance to them is the distance to that convex quad): a cell lying on a flat face made of
/// two triangles, across its diagonal, is no longer cut down to the tolerance (a 250 mm cube's
/// strips took 2.2 million queries).
double upper_bound(const Cell& c, const Vec3& m, double dm, int tm, const TriangleMesh& to) {
  double from_m = 0;
  for (const Vec3& q : c.p) from_m = std::max(from_m, (q - m).norm());
  double best = dm + from_m;
  for (int k = 0; k < 3; ++k) {
    double reach = 0;
    for (const Vec3& q : c.p) reach = std::max(reach, (q - c.p[k]).norm());
    best = std::min(best, c.d[k] + reach);
  }
  for (int t : {tm, c.near[0], c.near[1], c.near[2]}) {
    if (t < 0) continue;
    const auto& tri = to.triangles[t];
    const Vec3 &a = to.vertices[tri[0]], &b = to.vertices[tri[1]], &cc = to.vertices[tri[2]];
    double worst = 0;
    for (const Vec3& q : c.p) worst = std::max(worst, point_triangle_distance(q, a, b, cc));
    best = std::min(best, worst);
  }
  const std::array<int, 4> near = {tm, c.near[0], c.near[1], c.near[2]};
  for (int i = 0; i < 4 && best > 0; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const int t1 = near[i], t2 = near[j];
      if (t1 < 0 || t2 < 0 || t1 == t2) continue;
      if (const auto quad = convex_coplanar_pair(to, t1, t2)) {
        double worst = 0;
        for (const Vec3& q : c.p)
          worst = std::max(worst, std::min(point_triangle_distance(q, (*quad)[0], (*quad)[1],
                                                                   (*quad)[2]),
                                           point_triangle_distance(q, (*quad)[0], (*quad)[2],
                                                                   (*quad)[3])));
        best = std::min(best, worst);
      }
    }
  return best;
}

struct Max {
  double max = 0;    ///< the largest distance found at a point [mm]
  Vec3 at{0, 0, 0};  ///< that point (the first found, in a fixed order) [mm]
  double gap = 0;    ///< the true maximum is at most max + gap [mm]
  long samples = 0;
};

/// Largest distance from \p from to \p to, by branch and bound: every triangle starts with the
/// distances at its corners and centroid and an upper bound from them (upper_bound); the ones
/// with the highest bounds are cut into four at their edge midpoints, until no bound exceeds
/// the largest distance found by more than \p tolerance (or \p budget queries are spent: the
/// gap then says how far from certain it is). Only where the maximum could be is refined.
Max max_distance(const TriangleMesh& from, const TargetSurface& to, double tolerance, long budget) {
  const int threads = worker_count();
  const TriangleMesh& other = to.mesh();
  Max out;
  std::vector<double> at_vertex(from.vertices.size(), 0.0);
  std::vector<int> near_vertex(from.vertices.size(), -1);
  std::vector<char> used(from.vertices.size(), 0);
  for (const auto& t : from.triangles)
    for (int v : t) used[v] = 1;
  for_each_index(static_cast<int>(from.vertices.size()), threads, [&](int v) {
    if (!used[v]) return;
    const SurfacePoint sp = to.closest(from.vertices[v]);
    at_vertex[v] = sp.distance;
    near_vertex[v] = sp.triangle;
  });
  // A larger distance than the largest so far moves the point there (in index order, so the
  // point does not depend on the threads' timing).
  auto found = [&](double d, const Vec3& p) {
    if (d > out.max || out.samples == 0) {
      out.max = std::max(out.max, d);
      out.at = p;
    }
  };
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) found(at_vertex[v], from.vertices[v]), ++out.samples;
  // Each cell's bound needs its centroid's distance: computed in batches, in parallel.
  auto bound_all = [&](std::vector<Cell>& cells) {
    std::vector<double> centroid(cells.size());
    for_each_index(static_cast<int>(cells.size()), threads, [&](int i) {
      Cell& c = cells[i];
      const Vec3 m = (c.p[0] + c.p[1] + c.p[2]) / 3.0;
      const SurfacePoint sp = to.closest(m);
      centroid[i] = sp.distance;
      c.upper = upper_bound(c, m, sp.distance, sp.triangle, other);
    });
    for (std::size_t i = 0; i < cells.size(); ++i)
      found(centroid[i], (cells[i].p[0] + cells[i].p[1] + cells[i].p[2]) / 3.0);
    out.samples += static_cast<long>(cells.size());
  };
  std::vector<Cell> first;
  first.reserve(from.triangles.size());
  for (const auto& t : from.triangles)
    first.push_back({{from.vertices[t[0]], from.vertices[t[1]], from.vertices[t[2]]},
                     {at_vertex[t[0]], at_vertex[t[1]], at_vertex[t[2]]},
                     {near_vertex[t[0]], near_vertex[t[1]], near_vertex[t[2]]}});
  bound_all(first);
  std::priority_queue<Cell> open;
  double dropped = 0;  // the highest bound of a cell left uncut
  auto keep = [&](Cell& c) {
    if (c.upper > out.max + tolerance)
      open.push(std::move(c));
    else
      dropped = std::max(dropped, c.upper);
  };
  for (Cell& c : first) keep(c);
  constexpr std::size_t kBatch = 512;  // cells cut at once (their new points queried together)
  // Each cut costs 7 queries: 3 edge midpoints and 4 children's centroids.
  constexpr long kPerCut = 7;
  while (!open.empty() && open.top().upper > out.max + tolerance &&
         out.samples + kPerCut <= budget) {
    std::vector<Cell> cut;
    while (!open.empty() && cut.size() < kBatch && open.top().upper > out.max + tolerance &&
           out.samples + kPerCut * static_cast<long>(cut.size() + 1) <= budget) {
      cut.push_back(open.top());
      open.pop();
    }
    // Edge midpoints of every cut cell, then its four children.
    std::vector<std::array<SurfacePoint, 3>> mid(cut.size());
    for_each_index(static_cast<int>(cut.size()), threads, [&](int i) {
      const Cell& c = cut[i];
      for (int k = 0; k < 3; ++k) mid[i][k] = to.closest(0.5 * (c.p[k] + c.p[(k + 1) % 3]));
    });
    std::vector<Cell> children;
    children.reserve(4 * cut.size());
    for (std::size_t i = 0; i < cut.size(); ++i) {
      const Cell& c = cut[i];
      std::array<Vec3, 3> m;  // m[k] halves the edge from corner k to corner k + 1
      std::array<double, 3> md;
      std::array<int, 3> mt;
      for (int k = 0; k < 3; ++k) {
        m[k] = 0.5 * (c.p[k] + c.p[(k + 1) % 3]);
        md[k] = mid[i][k].distance;
        mt[k] = mid[i][k].triangle;
        found(md[k], m[k]);
      }
      children.push_back({{c.p[0], m[0], m[2]}, {c.d[0], md[0], md[2]}, {c.near[0], mt[0], mt[2]}});
      children.push_back({{m[0], c.p[1], m[1]}, {md[0], c.d[1], md[1]}, {mt[0], c.near[1], mt[1]}});
      children.push_back({{m[2], m[1], c.p[2]}, {md[2], md[1], c.d[2]}, {mt[2], mt[1], c.near[2]}});
      children.push_back({{m[0], m[1], m[2]}, {md[0], md[1], md[2]}, {mt[0], mt[1], mt[2]}});
    }
    out.samples += 3 * static_cast<long>(cut.size());
    bound_all(children);
    for (Cell& c : children) keep(c);
  }
  const double highest = std::max(dropped, open.empty() ? 0.0 : open.top().upper);
  out.gap = std::max(0.0, highest - out.max);
  return out;
}

long estimated_samples(const TriangleMesh& m, double spacing) {
  long n = 0;
  for (const auto& t : m.triangles)
    n += TriangleCells(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], spacing).count();
  return n;
}

}  // namespace

SurfaceDistance surface_distance(const TriangleMesh& a_in, const TriangleMesh& b_in,
                                 const SurfaceDistanceOptions& options) {
  if (!(options.sample_spacing > 0) || !std::isfinite(options.sample_spacing))
    throw InvalidInput("distance sample spacing must be a positive length in mm");
  const TriangleMesh a = without_degenerate(a_in), b = without_degenerate(b_in);
  if (a.triangles.empty() || b.triangles.empty())
    throw InvalidInput("surface distance: a surface has no triangle of positive area");
  constexpr long kMaxSamples = 50'000'000;
  double spacing = options.sample_spacing;
  // The means' queries: each surface at the spacing and again twice as coarse.
  auto needed = [&](double at) {
    return estimated_samples(a, at) + estimated_samples(b, at) + estimated_samples(a, 2 * at) +
           estimated_samples(b, 2 * at);
  };
  long samples = needed(spacing);
  if (options.max_samples > 0) {
    // Half of the budget for the means, a quarter for each maximum.
    const long budget = std::min(options.max_samples / 2, kMaxSamples);
    // Samples fall about with the square of the spacing; a few rounds settle the grid rounding.
    // At least one cell per triangle: no spacing goes below that.
    const long floor = 2 * static_cast<long>(a.triangles.size() + b.triangles.size());
    for (int round = 0; round < 64 && samples > budget && samples > floor; ++round) {
      spacing *= std::max(1.05, std::sqrt(static_cast<double>(samples) / budget));
      samples = needed(spacing);
    }
  }
  if (samples > kMaxSamples)
    throw InvalidInput("surface distance: sample spacing too fine for the model size");
  const TargetSurface sa(a), sb(b);
  // The maxima to within a quarter of the spacing (a uniform sampling at that spacing was only
  // sure to within the spacing), each with at most as many queries as the means.
  const double tolerance = 0.25 * spacing;
  const long budget = options.max_samples > 0 ? std::max<long>(1, options.max_samples / 4)
                                              : std::max<long>(samples, 100'000);
  const Max ab = max_distance(a, sb, tolerance, budget);
  const Max ba = max_distance(b, sa, tolerance, budget);
  const Mean ab_mean = mean_distance(a, sb, spacing), ba_mean = mean_distance(b, sa, spacing);
  // The same means from samples twice as far apart (a quarter of the queries): the centroid
  // rule's error falls with the square of the spacing, so the difference is an estimate (a
  // generous one) of what the finer means are off by.
  const Mean ab_coarse = mean_distance(a, sb, 2 * spacing);
  const Mean ba_coarse = mean_distance(b, sa, 2 * spacing);
  SurfaceDistance d;
  d.a_to_b_max = ab.max;
  d.a_to_b_at = ab.at;
  d.b_to_a_at = ba.at;
  d.a_to_b_mean = ab_mean.value();
  d.b_to_a_max = ba.max;
  d.b_to_a_mean = ba_mean.value();
  d.hausdorff = std::max(d.a_to_b_max, d.b_to_a_max);
  d.hausdorff_on_a = d.a_to_b_max >= d.b_to_a_max;
  d.hausdorff_gap = std::max(ab.max + ab.gap, ba.max + ba.gap) - d.hausdorff;
  d.mean = 0.5 * (d.a_to_b_mean + d.b_to_a_mean);
  d.mean_error_estimate = std::abs(d.mean - 0.5 * (ab_coarse.value() + ba_coarse.value()));
  d.samples = ab.samples + ba.samples + ab_mean.samples + ba_mean.samples + ab_coarse.samples +
              ba_coarse.samples;
  d.spacing = spacing;
  return d;
}

}  // namespace kerfab
