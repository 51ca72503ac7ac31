#include "kerfab/kerf/kerf.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>

#include "kerfab/core/errors.h"
#include "kerfab/core/parallel.h"

namespace kerfab {
namespace {

/// A cut may turn this far from its ruling to keep the spacing where rulings fan out: the beam
/// then twists with cos(15 deg) = 0.97 of the strip's rotation and bends out of plane with the
/// rest, a few MPa in MDF, far below its bending strength [rad].
constexpr double kMaxTurn = 15 * M_PI / 180;

/// A strip narrower than this across is a point: it holds no beam [mm].
constexpr double kNoWidth = 1e-6;

/// Parameters in [0, 1] where segment a-b crosses the polygons' boundaries.
std::vector<double> crossings(const Vec2& a, const Vec2& b, const std::vector<Polygon2>& polys) {
  std::vector<double> t;
  const Vec2 d = b - a;
  for (const auto& poly : polys)
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 p = poly[i], q = poly[(i + 1) % poly.size()], e = q - p;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (std::abs(den) < 1e-15) continue;
      const Vec2 w = p - a;
      const double u = (w.x() * e.y() - w.y() * e.x()) / den;  // along a-b
      const double v = (w.x() * d.y() - w.y() * d.x()) / den;  // along p-q
      if (u >= 0 && u <= 1 && v >= 0 && v < 1) t.push_back(u);
    }
  std::sort(t.begin(), t.end());
  return t;
}

double segment_distance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  auto side = [](const Vec2& o, const Vec2& p, const Vec2& q) { return cross2(p - o, q - o); };
  if (side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0) return 0.0;
  return std::min({distance_to_segment(a, c, d), distance_to_segment(b, c, d),
                   distance_to_segment(c, a, b), distance_to_segment(d, a, b)});
}

/// The twist the strip takes along its length: each internal ruling's fold spread evenly over
/// the stretch between the middles of its two sub-quads (the same stretch whose width enters the
/// beam), optionally smoothed; and the strip's width (the beams' length) along it.
class TwistProfile {
 public:
  TwistProfile(const StripFrame& frame, const std::vector<double>& fold, double smoothing) {
    const int n = frame.n;
    const std::vector<double>& s = frame.s;
    std::vector<double> mid(n);
    for (int f = 0; f < n; ++f) mid[f] = 0.5 * (s[f] + s[f + 1]);
    // Rate per stretch e = 1..n-1 over [mid[e-1], mid[e]].
    std::vector<double> rate(n, 0.0), width(n, 0.0), centre(n, 0.0);
    for (int e = 1; e < n; ++e) {
      width[e] = mid[e] - mid[e - 1];
      centre[e] = 0.5 * (mid[e] + mid[e - 1]);
      rate[e] = width[e] > 1e-9 ? fold[e] / width[e] : 0.0;
    }
    smoothed_.assign(n, 0.0);
    const double half = 0.5 * smoothing;
    for (int e = 1; e < n; ++e) {
      double used = rate[e];
      if (half > 0 && width[e] > 1e-9) {
        double sum = 0, weight = 0;
        for (int k = 1; k < n; ++k) {
          const double w = std::max(0.0, 1.0 - std::abs(centre[k] - centre[e]) / half) * width[k];
          sum += w * rate[k];
          weight += w;
        }
        if (weight > 0) used = sum / weight;
      }
      // A stretch of no width keeps its fold as a jump.
      smoothed_[e] = width[e] > 1e-9 ? used * width[e] : fold[e];
    }
    knot_s_.push_back(mid[0]);
    knot_phi_.push_back(0.0);
    for (int e = 1; e < n; ++e) {
      knot_s_.push_back(mid[e]);
      knot_phi_.push_back(knot_phi_.back() + smoothed_[e]);
    }
    ruling_s_ = s;
    for (int i = 0; i <= n; ++i)
      ruling_len_.push_back((frame.x[2 * i + 1] - frame.x[2 * i]).norm());
    length_ = s.back();
  }

  double length() const { return length_; }

  /// Smallest 2 l / kappa over the stretches with a width: the tightest bend (0: none bends)
  /// [mm^2].
  double tightest() const {
    double best = 0;
    for (std::size_t k = 1; k < knot_s_.size(); ++k) {
      const double a = knot_s_[k - 1], b = knot_s_[k];
      const double kappa = b > a ? (knot_phi_[k] - knot_phi_[k - 1]) / (b - a) : 0.0;
      if (!(kappa > 0)) continue;
      // Where the strip ends in a point there is no beam across it to break (a bust's strip
      // tip once asked for a model 55 000 km tall).
      const double w = width(a, b);
      if (!(w > kNoWidth)) continue;
      const double c = 2 * w / kappa;
      if (best == 0 || c < best) best = c;
    }
    return best;
  }
  /// The fold each internal ruling's stretch takes, after smoothing [rad] (index 1..n-1).
  const std::vector<double>& folds() const { return smoothed_; }

  /// Cumulative twist at strip coordinate \p at [rad].
  double twist(double at) const {
    if (at <= knot_s_.front()) return 0.0;
    if (at >= knot_s_.back()) return knot_phi_.back();
    const auto it = std::upper_bound(knot_s_.begin(), knot_s_.end(), at);
    const std::size_t k = static_cast<std::size_t>(it - knot_s_.begin());
    const double a = knot_s_[k - 1], b = knot_s_[k];
    const double u = b > a ? (at - a) / (b - a) : 1.0;
    return knot_phi_[k - 1] + u * (knot_phi_[k] - knot_phi_[k - 1]);
  }

  /// The shortest beam over [a, b]: the strip's narrowest width there [mm].
  double width(double a, double b) const {
    auto at = [&](double x) {
      const int n = static_cast<int>(ruling_s_.size()) - 1;
      const auto it = std::upper_bound(ruling_s_.begin(), ruling_s_.end(), x);
      const int i = std::clamp(static_cast<int>(it - ruling_s_.begin()) - 1, 0, n - 1);
      const double len = ruling_s_[i + 1] - ruling_s_[i];
      const double u = len > 0 ? std::clamp((x - ruling_s_[i]) / len, 0.0, 1.0) : 0.0;
      return (1 - u) * ruling_len_[i] + u * ruling_len_[i + 1];
    };
    double w = std::min(at(a), at(b));
    // The rulings strictly inside (a, b): one index range, as the coordinates are sorted.
    const auto first = std::upper_bound(ruling_s_.begin(), ruling_s_.end(), a);
    const auto last = std::lower_bound(first, ruling_s_.end(), b);
    for (auto it = first; it < last; ++it)
      w = std::min(w, ruling_len_[static_cast<std::size_t>(it - ruling_s_.begin())]);
    return w;
  }

 private:
  std::vector<double> knot_s_, knot_phi_, smoothed_, ruling_s_, ruling_len_;
  double length_ = 0;
};

class PatchKerfBuilder {
 public:
  PatchKerfBuilder(const Strips& s, const Flattening& f, const Joints& j, const Material& m,
                   const KerfOptions& o, int p)
      : s_(s), patch_(s.patches[p]), x_(f.patches[p].points), m_(m), o_(o), p_(p) {
    // The region cuts may use: the part's body (the flattened patch, so no cut enters a
    // tooth) without its slots, shrunk by the margin.
    body_ = polygon_intersection(j.parts[p].designed, flat_outline(s, f, p));
    region_ = polygon_offset(body_, -o.margin);
    allowed_ = m.yield_strength / m.safety;
  }

  PatchKerf run(std::vector<CriticalRegion>& critical) {
    const int n = static_cast<int>(patch_.faces.size());
    PatchKerf out;
    if (patch_.flat) {  // a facet is cut flat and never bent
      out.face_density.assign(n, 0.0);
      out.face_critical.assign(n, 0);
      return out;
    }
    const StripFrame frame(x_, n);
    const TwistProfile profile(frame, folds(), smoothing_width(s_, o_));
    for (int e = 1; e < n; ++e) {
      out.twist.push_back(profile.folds()[e]);
      out.positions.push_back(frame.s[e]);
    }
    out.tightest_bend = profile.tightest();
    std::vector<Plan> positions;  // cuts along the strip
    if (o_.constant_cuts_per_quad) {
      // Baseline: N cuts spread evenly over each coarse quad, never closer than the laser allows.
      int first = 0;
      for (std::size_t q = 0; q < patch_.quads.size(); ++q) {
        const int k = s_.quad_segments[patch_.quads[q]];
        const double a = frame.s[first], b = frame.s[first + k];
        for (int c = 0; c < *o_.constant_cuts_per_quad; ++c) {
          const double at = a + (c + 0.5) * (b - a) / *o_.constant_cuts_per_quad;
          if (positions.empty()) {
            positions.push_back({at, 0.0});
          } else if (const auto next = spaced_at(frame, positions.back(), at)) {
            positions.push_back(*next);
          }
        }
        first += k;
      }
    } else if (std::isfinite(allowed_) && m_.thickness > 0 && n >= 2) {
      positions = adaptive_positions(profile, frame);
    }
    place(positions, frame, out);
    assess(profile, frame, out, critical);
    return out;
  }

 private:
  const Strips& s_;
  const Patch& patch_;
  const std::vector<Vec2>& x_;
  const Material& m_;
  const KerfOptions& o_;
  int p_;
  std::vector<Polygon2> body_;                           // the part's body, before the margin
  std::vector<Polygon2> region_;                         // what cuts may use
  std::optional<std::vector<Polygon2>> default_region_;  // the same at the default margin
  double allowed_ = 0;                                   // tau_yield / safety [MPa]
  /// A planned cut that did not fit the part: where, and the size factor it fits from (0:
  /// unknown).
  struct Skipped {
    double at = 0, fit = 0;
  };
  std::vector<Skipped> skipped_;

  /// Fold across each internal ruling: the largest sector-normal angle at any of its rail
  /// vertices, in every row [rad].
  std::vector<double> folds() const {
    const int n = static_cast<int>(patch_.faces.size());
    const std::vector<int> lv = patch_.local_vertices();
    std::vector<double> fold(n, 0.0);
    for (int e = 1; e < n; ++e)
      for (int row = 0; row < patch_.rows(); ++row)
        for (int rail : {row, row + 1}) {
          const int v = lv[patch_.local(rail, e)];
          const auto& before = s_.faces[patch_.face(e - 1, row)];
          const auto& after = s_.faces[patch_.face(e, row)];
          fold[e] = std::max(fold[e], angle_between(sector_normal(s_.vertices, before, v),
                                                    sector_normal(s_.vertices, after, v)));
        }
    return fold;
  }

  /// Stress of the beam between strip coordinates a and b over the allowed stress [-].
  double ratio(const TwistProfile& t, double a, double b) const {
    const double phi = t.twist(b) - t.twist(a);
    if (!(phi > 0)) return 0.0;
    const double l = t.width(a, b);
    if (!(l > 0)) return std::numeric_limits<double>::infinity();
    return beam_stress(phi, b - a, l, m_.thickness, m_.shear_modulus) / allowed_;
  }

  /// The farthest b in (a, L] such that the beam [a, b] stays within \p limit (ratio).
  double reach(const TwistProfile& t, double a, double limit) const {
    const double end = t.length();
    if (ratio(t, a, end) <= limit) return end;
    double lo = a, hi = end;
    while (hi - lo > 1e-4) {
      const double mid = 0.5 * (lo + hi);
      (ratio(t, a, mid) <= limit ? lo : hi) = mid;
    }
    return lo;
  }

  /// A planned cut: where along the strip, and how far it turns from the ruling there [rad].
  struct Plan {
    double at = 0;
    double turn = 0;
  };

  /// The cut line of a plan, rail to rail: through the strip's middle at the position, along
  /// the ruling turned by the plan's angle.
  std::array<Vec2, 2> line(const StripFrame& frame, const Plan& c) const {
    const auto [r0, r1] = frame.section(c.at);
    const Vec2 mid = 0.5 * (r0 + r1);
    // Along the ruling itself (most cuts): no turn to apply, the same numbers.
    const Vec2 along = (r1 - r0).normalized();
    const Vec2 d = c.turn == 0 ? along : Vec2(Eigen::Rotation2Dd(c.turn) * along);
    const double half = 0.5 * (r1 - r0).norm() / (c.turn == 0 ? 1.0 : std::cos(c.turn));
    return {mid - half * d, mid + half * d};
  }

  /// The gap between the cut on \p u (a line()) and the cut \p b.
  double gap(const StripFrame& frame, const std::array<Vec2, 2>& u, const Plan& b) const {
    const auto v = line(frame, b);
    return segment_distance(u[0], u[1], v[0], v[1]);
  }

  /// A cut at \p at at least the minimum spacing from \p prev (its line \p prev_line): along
  /// its ruling if that keeps the spacing, else turned (at most kMaxTurn) as little as keeps
  /// it; none if no turn does.
  std::optional<Plan> spaced_at(const StripFrame& frame, const Plan& prev,
                                const std::array<Vec2, 2>& prev_line, double at) const {
    if (at - prev.at < o_.min_cut_spacing) return std::nullopt;
    Plan c{at, 0.0};
    if (gap(frame, prev_line, c) >= o_.min_cut_spacing) return c;
    // Turning towards the previous cut's direction opens a fan's narrow end.
    const auto [p0, p1] = prev_line;
    const auto [r0, r1] = frame.section(at);
    const Vec2 dp = (p1 - p0).normalized(), dr = (r1 - r0).normalized();
    const double parallel = std::atan2(cross2(dr, dp), dr.dot(dp));
    const double limit = std::clamp(parallel, -kMaxTurn, kMaxTurn);
    if (gap(frame, prev_line, {at, limit}) < o_.min_cut_spacing) return std::nullopt;
    double lo = 0, hi = 1;  // fraction of the limit
    while (hi - lo > 1e-3) {
      const double mid = 0.5 * (lo + hi);
      (gap(frame, prev_line, {at, mid * limit}) >= o_.min_cut_spacing ? hi : lo) = mid;
    }
    return Plan{at, hi * limit};
  }
  std::optional<Plan> spaced_at(const StripFrame& frame, const Plan& prev, double at) const {
    if (at - prev.at < o_.min_cut_spacing) return std::nullopt;
    return spaced_at(frame, prev, line(frame, prev), at);
  }

  /// The nearest cut at or after \p from that keeps the minimum spacing from \p prev, or none
  /// before the strip's end.
  std::optional<Plan> spaced(const StripFrame& frame, const Plan& prev, double from) const {
    const double end = frame.s.back();
    from = std::max(from, prev.at + o_.min_cut_spacing);
    if (from >= end) return std::nullopt;
    const auto prev_line = line(frame, prev);
    if (auto c = spaced_at(frame, prev, prev_line, from)) return c;
    if (!spaced_at(frame, prev, prev_line, end)) return std::nullopt;
    double lo = from, hi = end;
    while (hi - lo > 1e-4) {
      const double mid = 0.5 * (lo + hi);
      (spaced_at(frame, prev, prev_line, mid) ? hi : lo) = mid;
    }
    return spaced_at(frame, prev, prev_line, hi);
  }

  /// Cuts from the start of the strip, each as far from the last as a beam within \p limit
  /// reaches, but never closer to it than the minimum spacing: for a stress monotone in the
  /// beam's extent this greedy walk uses the fewest cuts that keep every beam within the limit.
  std::vector<Plan> walk(const TwistProfile& t, const StripFrame& frame, double limit) const {
    std::vector<Plan> cuts;
    Plan prev{-1e300, 0.0};  // the strip's start: no cut to keep away from
    double a = 0;
    for (;;) {
      const double b = reach(t, a, limit);
      if (b >= t.length()) break;
      const auto c = cuts.empty() ? std::optional<Plan>(Plan{b, 0.0}) : spaced(frame, prev, b);
      if (!c || c->at >= t.length() - 1e-9) break;
      cuts.push_back(*c);
      prev = *c;
      a = c->at;
    }
    return cuts;
  }

  /// The fewest cuts that keep every beam within the allowed stress, then spread so that the
  /// largest stress is as low as that count allows (bisection on the limit).
  std::vector<Plan> adaptive_positions(const TwistProfile& t, const StripFrame& frame) const {
    std::vector<Plan> best = walk(t, frame, 1.0);
    if (best.empty()) return best;
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 24; ++it) {
      const double mid = 0.5 * (lo + hi);
      std::vector<Plan> cuts = walk(t, frame, mid);
      if (cuts.size() <= best.size()) {
        hi = mid;
        best = std::move(cuts);
      } else {
        lo = mid;
      }
    }
    return best;
  }

  /// True when a cut on the line \p a0 - \p b0 (\p reach long, its middle on the cut's
  /// line) that did not fit with the options asked would fit with the default --bridge,
  /// --kerf-margin and --min-cut-length: the region the default margin leaves, crossed there,
  /// is at least a default bridge and cut long. Always false with the default options.
  bool fits_by_default(const Vec2& a0, const Vec2& b0, double reach) {
    const KerfOptions d;
    if (o_.bridge == d.bridge && o_.margin == d.margin && o_.min_cut_length == d.min_cut_length)
      return false;
    if (!default_region_)
      default_region_ = o_.margin == d.margin ? region_ : polygon_offset(body_, -d.margin);
    const auto stretch = middle_stretch(a0, b0, *default_region_);
    return stretch && (stretch->second - stretch->first) * reach >= d.bridge + d.min_cut_length;
  }

  /// The stretch [lo, hi] of the line \p a0 - \p b0 (as parameters along it) that lies inside
  /// \p region and holds the line's middle; none where the middle is outside.
  static std::optional<std::pair<double, double>> middle_stretch(
      const Vec2& a0, const Vec2& b0, const std::vector<Polygon2>& region) {
    const auto t = crossings(a0, b0, region);
    std::optional<std::pair<double, double>> out;
    for (std::size_t i = 0; i + 1 < t.size(); ++i) {
      const double m = 0.5 * (t[i] + t[i + 1]);
      if (!inside(a0 + m * (b0 - a0), region)) continue;
      if (t[i] <= 0.5 && t[i + 1] >= 0.5) out = {t[i], t[i + 1]};
    }
    return out;
  }

  void place(const std::vector<Plan>& plans, const StripFrame& frame, PatchKerf& out) {
    int index = 0;
    for (const Plan& plan : plans) {
      const double pos = plan.at;
      const auto [a, b] = line(frame, plan);
      // Extend across the outline, keep the stretch inside the shrunk part around the middle.
      const Vec2 d = (b - a).normalized();
      const double reach = (b - a).norm() + 20.0;
      const Vec2 a0 = 0.5 * (a + b) - 0.5 * reach * d, b0 = 0.5 * (a + b) + 0.5 * reach * d;
      // A planned cut that does not fit the part: where, and whether the options took its room.
      const auto skip = [&](double fit) {
        skipped_.push_back({pos, fit});
        ++out.skipped;
        out.skipped_by_options += fits_by_default(a0, b0, reach) ? 1 : 0;
      };
      const auto stretch = middle_stretch(a0, b0, region_);
      if (!stretch) {  // the part is too narrow here for a cut
        skip(0.0);
        continue;
      }
      const auto [lo, hi] = *stretch;
      Vec2 ca = a0 + lo * (b0 - a0), cb = a0 + hi * (b0 - a0);
      if (index % 2 == 0)
        ca += o_.bridge * d;
      else
        cb -= o_.bridge * d;
      if ((cb - ca).dot(d) < o_.min_cut_length) {  // too short to cut
        // What the strip's width across (b - a) loses to the joints, margins and bridge stays
        // as the model grows: the cut is the shortest one from the factor that adds the rest.
        const double across = (b - a).norm();
        skip(across > 0 ? (o_.min_cut_length + across - (cb - ca).dot(d)) / across : 0.0);
        continue;
      }
      ++index;
      out.cuts.push_back({ca, cb, pos, frame.face_at(pos)});
    }
  }

  /// The beams as placed: every stretch between consecutive cuts (and the strip's ends) is
  /// checked against the allowed stress; overstressed ones form the critical regions.
  void assess(const TwistProfile& t, const StripFrame& frame, PatchKerf& out,
              std::vector<CriticalRegion>& critical) const {
    const int n = static_cast<int>(patch_.faces.size());
    const std::vector<double>& s = frame.s;
    out.face_density.assign(n, 0.0);
    out.face_critical.assign(n, 0);
    std::vector<double> stops = {0.0};
    for (const auto& c : out.cuts) stops.push_back(c.position);
    stops.push_back(t.length());
    out.min_spacing = 0;
    for (std::size_t i = 1; i < out.cuts.size(); ++i) {
      const double gap = out.cuts[i].position - out.cuts[i - 1].position;
      if (i == 1 || gap < out.min_spacing) out.min_spacing = gap;
    }
    bool open = false;
    const bool stressed = std::isfinite(allowed_) && m_.thickness > 0;
    for (std::size_t i = 0; i + 1 < stops.size(); ++i) {
      const double a = stops[i], b = stops[i + 1];
      const double r = stressed ? ratio(t, a, b) : 0.0;
      out.stress_ratio = std::max(out.stress_ratio, r);
      if (r <= 1.0 + 1e-6) {
        open = false;
        continue;
      }
      if (!open) {
        CriticalRegion c;
        c.patch = p_;
        c.start = a;
        c.end = b;
        c.spacing = reach(t, a, 1.0) - a;
        c.stress_ratio = r;
        critical.push_back(std::move(c));
        open = true;
      }
      CriticalRegion& c = critical.back();
      const double needed = reach(t, a, 1.0) - a;  // the widest beam the bend allows here
      c.end = b;
      c.spacing = std::min(c.spacing, needed);
      c.stress_ratio = std::max(c.stress_ratio, r);
      c.cuts += i + 1 < stops.size() - 1 ? 1 : 0;
      // A bend that needs beams under the minimum spacing explains it first; else a planned
      // cut that did not fit the part; else the spacing of converging cut lines (a fan).
      bool skipped = false, unknown = false;
      double fit = 0;
      for (const Skipped& k : skipped_)
        if (k.at > c.start && k.at < b) {
          skipped = true;
          unknown = unknown || !(k.fit > 0);
          fit = std::max(fit, k.fit);
        }
      c.fit_factor = unknown ? 0.0 : fit;
      c.cause = c.spacing < o_.min_cut_spacing - 1e-6 ? CriticalCause::kTooDense
                : skipped                             ? CriticalCause::kTooNarrow
                                                      : CriticalCause::kFan;
      for (int f = frame.face_at(a); f <= frame.face_at(b); ++f) out.face_critical[f] = 1;
    }
    // Where each region of this patch lies: its quads and its middle in 3D.
    for (CriticalRegion& c : critical) {
      if (c.patch != p_ || !c.quads.empty()) continue;
      std::set<int> quads;
      Vec3 sum = Vec3::Zero();
      int count = 0;
      for (int f = frame.face_at(c.start); f <= frame.face_at(c.end); ++f)
        for (int row = 0; row < patch_.rows(); ++row) {
          const int face = patch_.face(f, row);
          quads.insert(s_.face_quad[face]);
          for (int v : s_.faces[face]) sum += s_.vertices[v], ++count;
        }
      c.quads.assign(quads.begin(), quads.end());
      c.centre = sum / std::max(count, 1);
    }
    // Density at each sub-quad: one over the spacing of the two cuts around its middle.
    for (int f = 0; f < n; ++f) {
      const double centre = 0.5 * (s[f] + s[f + 1]);
      auto it = std::lower_bound(out.cuts.begin(), out.cuts.end(), centre,
                                 [](const KerfCut& c, double v) { return c.position < v; });
      if (it == out.cuts.begin() || it == out.cuts.end()) continue;
      const double gap = it->position - std::prev(it)->position;
      out.face_density[f] = gap > 0 ? 1.0 / gap : 0.0;
    }
  }
};

/// What PatchKerfBuilder reads for patch \p p, as bytes: the material, the options and the
/// smoothing width, the patch's sub-quads row by row (each corner's 3D point and its place
/// among the patch's own vertices, which says how the sub-quads join, and the coarse quad
/// under each), its flattened points and outline, and its part's designed outline. Not the
/// patch's number or the vertices' ids, which differ between builds.
std::string patch_key(const Strips& s, const Flattening& f, const Joints& j, const Material& m,
                      const KerfOptions& o, double smoothing, int p) {
  std::string key;
  auto put = [&key](const auto& value) {
    key.append(reinterpret_cast<const char*>(&value), sizeof(value));
  };
  auto put_points = [&](const std::vector<Vec2>& points) {
    put(points.size());
    for (const Vec2& v : points) put(v.x()), put(v.y());
  };
  put(m.thickness), put(m.shear_modulus), put(m.yield_strength), put(m.safety);
  put(o.min_cut_spacing), put(o.min_cut_length), put(o.bridge), put(o.margin), put(smoothing);
  put(o.constant_cuts_per_quad.has_value()), put(o.constant_cuts_per_quad.value_or(0));
  const Patch& patch = s.patches[p];
  put(patch.flat), put(patch.faces.size()), put(patch.rows());
  // The patch's own vertices: each one's first place among them (equal ids, equal places).
  const std::vector<int> lv = patch.local_vertices();
  std::unordered_map<int, int> first;
  for (std::size_t k = 0; k < lv.size(); ++k)
    put(first.try_emplace(lv[k], static_cast<int>(k)).first->second);
  for (int row = 0; row < patch.rows(); ++row)
    for (std::size_t i = 0; i < patch.faces.size(); ++i) {
      const int face = patch.face(static_cast<int>(i), row);
      put(s.face_quad[face]);
      for (int v : s.faces[face]) {
        const auto at = first.find(v);
        put(at == first.end() ? -1 : at->second);
        put(s.vertices[v].x()), put(s.vertices[v].y()), put(s.vertices[v].z());
      }
    }
  for (int q : patch.quads) put(s.quad_segments[q]);
  for (const OutlineEdge& e : patch.outline()) put(e.v[0]);
  put_points(f.patches[p].points);
  put_points(j.parts[p].designed);
  return key;
}

}  // namespace

std::size_t PatchPlacement::bytes() const {
  std::size_t n =
      sizeof(PatchPlacement) +
      sizeof(double) * (kerf.twist.size() + kerf.positions.size() + kerf.face_density.size()) +
      sizeof(KerfCut) * kerf.cuts.size() + kerf.face_critical.size();
  for (const CriticalRegion& c : critical)
    n += sizeof(CriticalRegion) + sizeof(int) * c.quads.size();
  return n;
}

std::string to_string(CriticalCause cause) {
  switch (cause) {
    case CriticalCause::kTooDense:
      return "too_dense";
    case CriticalCause::kTooNarrow:
      return "too_narrow";
    case CriticalCause::kFan:
      return "fan";
  }
  return "";
}

double smoothing_width(const Strips& strips, const KerfOptions& options) {
  return options.smoothing.value_or(2.0 * strips.target_facet_size);
}

double bend_scale(double tightest_bend, const Material& m, double spacing) {
  if (!(tightest_bend > 0) || !(m.thickness > 0) || !std::isfinite(m.yield_strength)) return 1.0;
  const double g = m.shear_modulus / (m.yield_strength / m.safety);
  const double need = g * spacing * std::sqrt(m.thickness * m.thickness + spacing * spacing);
  return std::max(1.0, std::sqrt(need / tightest_bend));
}

double beam_stress(double twist, double width, double length, double thickness,
                   double shear_modulus) {
  return shear_modulus * twist * 0.5 * std::sqrt(thickness * thickness + width * width) / length;
}

double beams_needed(double angle, double width, double length, double thickness,
                    double shear_over_yield) {
  if (!(length > 0) || !(angle > 0) || !std::isfinite(shear_over_yield)) return 0.0;
  const double a = std::pow(angle * shear_over_yield / length, 2);
  const double h2 = thickness * thickness;
  const double z = a * h2 / 8 + std::sqrt(a * a * h2 * h2 / 64 + a * width * width / 4);
  return std::sqrt(z);
}

void check_kerf_options(const Material& m, const Machine& machine, const KerfOptions& options) {
  if (!(m.thickness >= 0) || !std::isfinite(m.thickness))
    throw InvalidInput("--thickness must be >= 0 mm");
  if (!(m.shear_modulus > 0)) throw InvalidInput("--shear-modulus must be > 0 MPa");
  if (!(m.yield_strength > 0)) throw InvalidInput("--yield-strength must be > 0 MPa");
  if (!(m.safety >= 1)) throw InvalidInput("--safety must be >= 1");
  if (!(options.min_cut_spacing > 0)) throw InvalidInput("--min-cut-spacing must be > 0 mm");
  if (!(options.min_cut_length > 0)) throw InvalidInput("--min-cut-length must be > 0 mm");
  if (options.smoothing && !(*options.smoothing >= 0))
    throw InvalidInput("--kerf-smoothing must be >= 0 mm");
  if (!(options.bridge >= 0) || !(options.margin >= 0))
    throw InvalidInput("--bridge and --kerf-margin must be >= 0 mm");
  if (options.constant_cuts_per_quad && *options.constant_cuts_per_quad < 0)
    throw InvalidInput("--constant-density must be >= 0 cuts per quad");
  if (m.thickness > 0 && !(options.min_cut_spacing > machine.kerf_width)) {
    std::ostringstream why;
    why << "--min-cut-spacing " << options.min_cut_spacing << " mm is no wider than the laser's "
        << "kerf (--kerf-width " << machine.kerf_width << " mm): neighbouring cuts would overlap "
        << "and burn away the beam between them";
    throw InvalidInput(why.str());
  }
}

KerfResult place_kerf_cuts(const Strips& strips, const Flattening& flat, const Joints& joints,
                           const Material& m, const Machine& machine, const KerfOptions& options,
                           KerfMemo* memo) {
  check_kerf_options(m, machine, options);
  if (joints.parts.size() != strips.patches.size() || flat.patches.size() != strips.patches.size())
    throw InvalidInput("kerf: flattening or joints do not belong to these strips");
  KerfResult r;
  r.smoothing = smoothing_width(strips, options);
  r.quad_cuts.assign(strips.quad_segments.size(), 0);
  // Patches in parallel (each builder reads only its own patch), collected in patch order.
  const int np = static_cast<int>(strips.patches.size());
  r.patches.resize(np);
  std::vector<std::vector<CriticalRegion>> critical(np);
  for_each_index(np, hardware_threads(), [&](int p) {
    std::string key;
    if (memo) {
      key = patch_key(strips, flat, joints, m, options, r.smoothing, p);
      if (auto hit = memo->find(key)) {
        r.patches[p] = std::move(hit->kerf);
        critical[p] = std::move(hit->critical);
        for (CriticalRegion& c : critical[p]) c.patch = p;
        return;
      }
    }
    r.patches[p] = PatchKerfBuilder(strips, flat, joints, m, options, p).run(critical[p]);
    if (memo) memo->insert(std::move(key), {r.patches[p], critical[p]});
  });
  for (auto& list : critical) r.critical.insert(r.critical.end(), list.begin(), list.end());
  for (std::size_t p = 0; p < strips.patches.size(); ++p) {
    r.skipped += r.patches[p].skipped;
    r.skipped_by_options += r.patches[p].skipped_by_options;
    for (const auto& c : r.patches[p].cuts) {
      ++r.cuts;
      r.cut_length += (c.b - c.a).norm();
      for (int row = 0; row < strips.patches[p].rows(); ++row)
        r.quad_cuts[strips.face_quad[strips.patches[p].face(c.face, row)]] += 1;
    }
  }
  for (int q : r.quad_cuts) r.max_cuts_per_quad = std::max(r.max_cuts_per_quad, q);
  for (const PatchKerf& p : r.patches)
    if (p.tightest_bend > 0 && (r.tightest_bend == 0 || p.tightest_bend < r.tightest_bend))
      r.tightest_bend = p.tightest_bend;
  CuttingEstimate& c = r.cutting;
  for (const auto& part : joints.parts)
    for (std::size_t i = 0; i < part.cut.size(); ++i)
      c.outline_length += (part.cut[(i + 1) % part.cut.size()] - part.cut[i]).norm();
  c.kerf_length = r.cut_length;
  c.paths = r.cuts + static_cast<int>(joints.parts.size());
  c.minutes = cutting_minutes(c.total_length(), c.paths, machine);
  return r;
}

}  // namespace kerfab
