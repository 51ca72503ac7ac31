#include "kerfab/eval/surface_distance.h"

#include <algorithm>
#include <cmath>

#include "kerfab/adapters/target_surface.h"
#include "kerfab/core/errors.h"
#include "kerfab/core/parallel.h"

namespace kerfab {
namespace {

TriangleMesh without_degenerate(const TriangleMesh& m) {
  TriangleMesh out;
  out.vertices = m.vertices;
  for (const auto& t : m.triangles) {
    const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    if (n.norm() > 1e-12) out.triangles.push_back(t);
  }
  return out;
}

int grid_steps(const TriangleMesh& m, const std::array<int, 3>& t, double spacing) {
  double longest = 0;
  for (int k = 0; k < 3; ++k)
    longest = std::max(longest, (m.vertices[t[(k + 1) % 3]] - m.vertices[t[k]]).norm());
  return std::max(1, static_cast<int>(std::ceil(longest / spacing)));
}

struct OneSided {
  double max = 0, weighted_sum = 0, area = 0;
  long samples = 0;
};

OneSided one_sided(const TriangleMesh& from, const TargetSurface& to, double spacing) {
  const int threads = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  std::vector<OneSided> parts(threads);
  const int nt = static_cast<int>(from.triangles.size());
  auto work = [&](int id) {
    OneSided& r = parts[id];
    for (int ti = id; ti < nt; ti += threads) {
      const auto& t = from.triangles[ti];
      const Vec3 &a = from.vertices[t[0]], &b = from.vertices[t[1]], &c = from.vertices[t[2]];
      const int n = grid_steps(from, t, spacing);
      const double sub_area = 0.5 * (b - a).cross(c - a).norm() / (n * n);
      auto at = [&](double i, double j) { return a + (i / n) * (b - a) + (j / n) * (c - a); };
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
          r.max = std::max(r.max, to.closest(at(i, j)).distance);
          ++r.samples;
          // Centroids of the (up to two) sub-triangles with this grid point as corner.
          if (i + j < n) {
            const double d = to.closest(at(i + 1.0 / 3, j + 1.0 / 3)).distance;
            r.max = std::max(r.max, d);
            r.weighted_sum += d * sub_area;
            r.area += sub_area;
            ++r.samples;
          }
          if (i + j < n - 1) {
            const double d = to.closest(at(i + 2.0 / 3, j + 2.0 / 3)).distance;
            r.max = std::max(r.max, d);
            r.weighted_sum += d * sub_area;
            r.area += sub_area;
            ++r.samples;
          }
        }
    }
  };
  run_parallel(threads, work);
  OneSided total;
  for (const auto& p : parts) {
    total.max = std::max(total.max, p.max);
    total.weighted_sum += p.weighted_sum;
    total.area += p.area;
    total.samples += p.samples;
  }
  return total;
}

long estimated_samples(const TriangleMesh& m, double spacing) {
  long n = 0;
  for (const auto& t : m.triangles) {
    const long k = grid_steps(m, t, spacing);
    n += 2 * k * k + 3 * k;
  }
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
  auto needed = [&](double at) { return estimated_samples(a, at) + estimated_samples(b, at); };
  long samples = needed(spacing);
  if (options.max_samples > 0) {
    const long budget = std::min(options.max_samples, kMaxSamples);
    // Samples fall about with the square of the spacing; a few rounds settle the grid rounding.
    for (int round = 0; round < 64 && samples > budget; ++round) {
      spacing *= std::max(1.05, std::sqrt(static_cast<double>(samples) / budget));
      samples = needed(spacing);
    }
  }
  if (samples > kMaxSamples)
    throw InvalidInput("surface distance: sample spacing too fine for the model size");
  const TargetSurface sa(a), sb(b);
  const OneSided ab = one_sided(a, sb, spacing);
  const OneSided ba = one_sided(b, sa, spacing);
  SurfaceDistance d;
  d.a_to_b_max = ab.max;
  d.a_to_b_mean = ab.area > 0 ? ab.weighted_sum / ab.area : 0;
  d.b_to_a_max = ba.max;
  d.b_to_a_mean = ba.area > 0 ? ba.weighted_sum / ba.area : 0;
  d.hausdorff = std::max(d.a_to_b_max, d.b_to_a_max);
  d.mean = 0.5 * (d.a_to_b_mean + d.b_to_a_mean);
  d.samples = ab.samples + ba.samples;
  d.spacing = spacing;
  return d;
}

}  // namespace kerfab
