#include "kerfab/kerf/kerf.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

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

bool inside(const Vec2& p, const std::vector<Polygon2>& polys) {  // non-zero over all rings
  int winding = 0;
  for (const auto& poly : polys)
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
      const double c = (b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y());
      if (a.y() <= p.y() && b.y() > p.y() && c > 0) ++winding;
      if (a.y() > p.y() && b.y() <= p.y() && c < 0) --winding;
    }
  return winding != 0;
}

class PatchKerfBuilder {
 public:
  PatchKerfBuilder(const Strips& s, const Flattening& f, const Joints& j, const Material& m,
                   const KerfOptions& o, int p)
      : s_(s), patch_(s.patches[p]), x_(f.patches[p].points), m_(m), o_(o), p_(p) {
    // The region cuts may use: the part's body (the flattened patch, so no cut enters a
    // tooth) without its slots, shrunk by the margin.
    region_ =
        polygon_offset(polygon_intersection(j.parts[p].designed, flat_outline(s, f, p)), -o.margin);
  }

  PatchKerf run(std::vector<CriticalRegion>& critical) {
    const int n = static_cast<int>(patch_.faces.size());
    PatchKerf out;
    const StripFrame frame(x_, n);
    const std::vector<double>& s = frame.s;
    std::vector<double> positions;  // cut positions along the strip
    if (o_.constant_cuts_per_quad) {
      // Baseline: N cuts spread evenly over each coarse quad.
      int first = 0;
      for (std::size_t q = 0; q < patch_.quads.size(); ++q) {
        const int k = s_.quad_segments[patch_.quads[q]];
        const double a = s[first], b = s[first + k];
        for (int c = 0; c < *o_.constant_cuts_per_quad; ++c)
          positions.push_back(a + (c + 0.5) * (b - a) / *o_.constant_cuts_per_quad);
        first += k;
      }
    } else if (n >= 2) {
      positions = adaptive_positions(s, out);
    }
    place(positions, frame, out, critical);
    return out;
  }

 private:
  const Strips& s_;
  const Patch& patch_;
  const std::vector<Vec2>& x_;
  const Material& m_;
  const KerfOptions& o_;
  int p_;
  std::vector<Polygon2> region_;

  Vec2 rail(int ruling, int r) const { return x_[2 * ruling + r]; }
  double face_width(int f) const {
    return std::min((rail(f + 1, 0) - rail(f, 0)).norm(), (rail(f + 1, 1) - rail(f, 1)).norm());
  }

  std::vector<double> adaptive_positions(const std::vector<double>& s, PatchKerf& out) {
    const int n = static_cast<int>(patch_.faces.size());
    const Material& m = m_;
    const double shear_over_yield = m.shear_modulus / (m.yield_strength / m.safety);
    std::vector<double> beams(n + 1, 0.0), width(n + 1, 0.0);
    for (int e = 1; e < n; ++e) {
      width[e] = 0.5 * std::min(face_width(e - 1), face_width(e));
      const double length = (rail(e, 1) - rail(e, 0)).norm();
      double angle = 0;  // largest normal angle across the ruling, at either end
      for (int r = 0; r < 2; ++r) {
        const int v = patch_.rulings[e][r];
        angle = std::max(angle,
                         angle_between(sector_normal(s_.vertices, s_.faces[patch_.faces[e - 1]], v),
                                       sector_normal(s_.vertices, s_.faces[patch_.faces[e]], v)));
      }
      beams[e] = beams_needed(angle, width[e], length, m.thickness, shear_over_yield);
    }
    // Smooth with a tent kernel along the strip.
    std::vector<double> smooth(n + 1, 0.0);
    const double half = 0.5 * o_.smoothing;
    for (int e = 1; e < n; ++e) {
      if (half <= 0) {
        smooth[e] = beams[e];
        continue;
      }
      double sum = 0, weight = 0;
      for (int k = 1; k < n; ++k) {
        const double w = std::max(0.0, 1.0 - std::abs(s[k] - s[e]) / half);
        sum += w * beams[k];
        weight += w;
      }
      smooth[e] = weight > 0 ? sum / weight : beams[e];
    }
    for (int e = 1; e < n; ++e) {
      out.beams.push_back(smooth[e]);
      out.positions.push_back(s[e]);
    }
    // Integrate: ruling e owns the stretch from the middle of face e-1 to the middle of face e,
    // holding smooth[e] beams; scale the total up to a whole number of beams and cut where the
    // running integral crosses each whole number (paper Fig. 8).
    double total = 0;
    for (int e = 1; e < n; ++e) total += smooth[e];
    std::vector<double> positions;
    if (total <= 1e-9) return positions;
    const int count = static_cast<int>(std::ceil(total - 1e-9));
    const double scale = count / total;
    double before = 0;
    int next = 1;
    for (int e = 1; e < n && next < count; ++e) {
      const double here = scale * smooth[e];
      const double a = 0.5 * (s[e - 1] + s[e]), b = 0.5 * (s[e] + s[e + 1]);
      while (next < count && before + here >= next - 1e-12) {
        const double u = here > 0 ? (next - before) / here : 0.5;
        positions.push_back(a + std::clamp(u, 0.0, 1.0) * (b - a));
        ++next;
      }
      before += here;
    }
    return positions;
  }

  void place(const std::vector<double>& positions, const StripFrame& frame, PatchKerf& out,
             std::vector<CriticalRegion>& critical) {
    const int n = static_cast<int>(patch_.faces.size());
    const std::vector<double>& s = frame.s;
    out.face_density.assign(n, 0.0);
    out.face_critical.assign(n, 0);
    auto face_at = [&](double pos) { return frame.face_at(pos); };
    int index = 0;
    for (double pos : positions) {
      const auto [a, b] = frame.section(pos);
      // Extend across the outline, keep the stretch inside the shrunk part around the middle.
      const Vec2 d = (b - a).normalized();
      const double reach = (b - a).norm() + 20.0;
      const Vec2 a0 = 0.5 * (a + b) - 0.5 * reach * d, b0 = 0.5 * (a + b) + 0.5 * reach * d;
      const auto t = crossings(a0, b0, region_);
      double lo = -1, hi = -1;
      for (std::size_t i = 0; i + 1 < t.size(); ++i) {
        const double m = 0.5 * (t[i] + t[i + 1]);
        if (!inside(a0 + m * (b0 - a0), region_)) continue;
        if (t[i] <= 0.5 && t[i + 1] >= 0.5) lo = t[i], hi = t[i + 1];
      }
      if (lo < 0) continue;  // the part is too narrow here for a cut
      Vec2 ca = a0 + lo * (b0 - a0), cb = a0 + hi * (b0 - a0);
      if (index % 2 == 0)
        ca += o_.bridge * d;
      else
        cb -= o_.bridge * d;
      ++index;
      if ((cb - ca).dot(d) <= 0) continue;
      out.cuts.push_back({ca, cb, pos, face_at(pos)});
    }
    // Density at each sub-quad: one over the spacing of the two cuts around its middle.
    for (int f = 0; f < n; ++f) {
      const double centre = 0.5 * (s[f] + s[f + 1]);
      auto it = std::lower_bound(out.cuts.begin(), out.cuts.end(), centre,
                                 [](const KerfCut& c, double v) { return c.position < v; });
      if (it == out.cuts.begin() || it == out.cuts.end()) {
        out.face_density[f] = 0;
        continue;
      }
      const double gap = it->position - std::prev(it)->position;
      out.face_density[f] = gap > 0 ? 1.0 / gap : 0.0;
    }
    out.min_spacing = 0;
    bool open = false;
    for (std::size_t i = 1; i < out.cuts.size(); ++i) {
      const double a = out.cuts[i - 1].position, b = out.cuts[i].position, gap = b - a;
      if (i == 1 || gap < out.min_spacing) out.min_spacing = gap;
      if (gap >= o_.min_cut_spacing) {
        open = false;
        continue;
      }
      if (!open) critical.push_back({p_, a, a, gap, 1});
      open = true;
      CriticalRegion& c = critical.back();
      c.end = b;
      c.spacing = std::min(c.spacing, gap);
      ++c.cuts;
      for (int f = face_at(a); f <= face_at(b); ++f) out.face_critical[f] = 1;
    }
  }
};

}  // namespace

double beams_needed(double angle, double width, double length, double thickness,
                    double shear_over_yield) {
  if (!(length > 0) || !(angle > 0) || !std::isfinite(shear_over_yield)) return 0.0;
  const double a = std::pow(angle * shear_over_yield / length, 2);
  const double h2 = thickness * thickness;
  const double z = a * h2 / 8 + std::sqrt(a * a * h2 * h2 / 64 + a * width * width / 4);
  return std::sqrt(z);
}

KerfResult place_kerf_cuts(const Strips& strips, const Flattening& flat, const Joints& joints,
                           const Material& m, const Machine& machine, const KerfOptions& options) {
  if (!(m.thickness >= 0) || !std::isfinite(m.thickness))
    throw InvalidInput("--thickness must be >= 0 mm");
  if (!(m.shear_modulus > 0)) throw InvalidInput("--shear-modulus must be > 0 MPa");
  if (!(m.yield_strength > 0)) throw InvalidInput("--yield-strength must be > 0 MPa");
  if (!(m.safety >= 1)) throw InvalidInput("--safety must be >= 1");
  if (!(options.min_cut_spacing > 0)) throw InvalidInput("--min-cut-spacing must be > 0 mm");
  if (!(options.smoothing >= 0)) throw InvalidInput("--kerf-smoothing must be >= 0 mm");
  if (!(options.bridge >= 0) || !(options.margin >= 0))
    throw InvalidInput("--bridge and --kerf-margin must be >= 0 mm");
  if (options.constant_cuts_per_quad && *options.constant_cuts_per_quad < 0)
    throw InvalidInput("--constant-density must be >= 0 cuts per quad");
  if (joints.parts.size() != strips.patches.size() || flat.patches.size() != strips.patches.size())
    throw InvalidInput("kerf: flattening or joints do not belong to these strips");
  KerfResult r;
  r.quad_cuts.assign(strips.quad_segments.size(), 0);
  for (std::size_t p = 0; p < strips.patches.size(); ++p) {
    r.patches.push_back(
        PatchKerfBuilder(strips, flat, joints, m, options, static_cast<int>(p)).run(r.critical));
    for (const auto& c : r.patches.back().cuts) {
      ++r.cuts;
      r.cut_length += (c.b - c.a).norm();
      r.quad_cuts[strips.face_quad[strips.patches[p].faces[c.face]]] += 1;
    }
  }
  for (int q : r.quad_cuts) r.max_cuts_per_quad = std::max(r.max_cuts_per_quad, q);
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
