#include "kerfab/output/render3d.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>

namespace kerfab {
namespace {

/// Model point with the up axis as z, then turned about z and tilted about x.
Vec3 turned(const Vec3& p, const ViewOptions& o) {
  const Vec3 q(p[(o.up + 1) % 3], p[(o.up + 2) % 3], p[o.up]);
  const double ca = std::cos(o.azimuth), sa = std::sin(o.azimuth);
  const double x = ca * q.x() - sa * q.y(), y = sa * q.x() + ca * q.y();
  const double ce = std::cos(o.elevation), se = std::sin(o.elevation);
  return {x, ce * y - se * q.z(), se * y + ce * q.z()};
}

struct Extent {
  double x0 = 1e300, x1 = -1e300, z0 = 1e300, z1 = -1e300;
};

Extent extent(const std::vector<Vec3>& points, const ViewOptions& o) {
  Extent e;
  for (const Vec3& p : points) {
    const Vec3 t = turned(p, o);
    e.x0 = std::min(e.x0, t.x());
    e.x1 = std::max(e.x1, t.x());
    e.z0 = std::min(e.z0, t.z());
    e.z1 = std::max(e.z1, t.z());
  }
  return e;
}

}  // namespace

View3::View3(const std::vector<Vec3>& points, const ViewOptions& options, double x, double y,
             double w, double h)
    : options_(options) {
  const Extent e = extent(points, options);
  const double span_x = std::max(e.x1 - e.x0, 1e-9), span_z = std::max(e.z1 - e.z0, 1e-9);
  scale_ = 0.95 * std::min(w / span_x, h / span_z);
  cx_ = (e.x0 + e.x1) / 2;
  cz_ = (e.z0 + e.z1) / 2;
  ox_ = x + w / 2;
  oy_ = y + h / 2;
}

double View3::aspect(const std::vector<Vec3>& points, const ViewOptions& options) {
  const Extent e = extent(points, options);
  return std::max(e.z1 - e.z0, 1e-9) / std::max(e.x1 - e.x0, 1e-9);
}

Vec3 View3::turn(const Vec3& p) const { return turned(p, options_); }

std::array<double, 2> View3::screen_of_turned(const Vec3& t) const {
  return {ox_ + scale_ * (t.x() - cx_), oy_ - scale_ * (t.z() - cz_)};
}

std::vector<Vec3> corners_of(const std::vector<Face3>& faces) {
  std::vector<Vec3> out;
  for (const Face3& f : faces) out.insert(out.end(), f.corners.begin(), f.corners.end());
  return out;
}

FacePainter::FacePainter(const View3& view, const std::vector<Face3>& faces) : faces_(faces) {
  const Vec3 light = Vec3(-0.5, -0.6, 0.6).normalized();
  std::vector<Vec3> t;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& c = faces[f].corners;
    if (c.size() < 3) continue;
    t.clear();
    for (const Vec3& p : c) t.push_back(view.turn(p));
    Vec3 n = Vec3::Zero(), centre = Vec3::Zero();  // Newell's normal, in view coordinates
    for (std::size_t k = 0; k < c.size(); ++k) {
      n += t[k].cross(t[(k + 1) % c.size()]);
      centre += t[k];
    }
    if (n.norm() < 1e-300) continue;
    n.normalize();
    const bool back = n.y() > 0;  // the viewer looks along +y
    const double lambert = std::max(0.0, (back ? -n : n).dot(light));
    order_.push_back({centre.y() / c.size(), f, back ? 0.45 + 0.3 * lambert : 0.35 + 0.65 * lambert,
                      screen_.size()});
    for (const Vec3& p : t) screen_.push_back(view.screen_of_turned(p));
  }
  std::stable_sort(order_.begin(), order_.end(),
                   [](const Drawn& a, const Drawn& b) { return a.depth > b.depth; });
}

void FacePainter::draw(cairo_t* cr, const Fill& fill, bool flat, double line_scale) const {
  cairo_save(cr);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  if (flat) cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
  Rgb colour;
  for (const Drawn& d : order_) {
    const Face3& f = faces_[d.face];
    if (!fill(f, colour)) continue;
    const auto* s = screen_.data() + d.first;
    const std::size_t n = f.corners.size();
    cairo_move_to(cr, s[0][0], s[0][1]);
    for (std::size_t k = 1; k < n; ++k) cairo_line_to(cr, s[k][0], s[k][1]);
    cairo_close_path(cr);
    cairo_set_source_rgb(cr, colour[0] * d.shade, colour[1] * d.shade, colour[2] * d.shade);
    if (flat) {
      cairo_fill(cr);
    } else {
      cairo_fill_preserve(cr);
      cairo_set_line_width(cr, 0.6);  // closes the hairline gaps between neighbouring faces
      cairo_stroke(cr);
    }
    for (const SideStroke& side : f.sides) {
      const auto& a = s[side.side % n];
      const auto& b = s[(side.side + 1) % n];
      cairo_set_source_rgba(cr, side.colour[0], side.colour[1], side.colour[2], side.opacity);
      const double w = side.width * line_scale;
      if (flat) {
        // A filled bar with square ends instead of a stroke: the same pixels without
        // antialiasing, at a fraction of the stroker's cost.
        const double dx = b[0] - a[0], dy = b[1] - a[1], len = std::hypot(dx, dy);
        if (!(len > 0)) continue;
        const double ux = dx / len * 0.5 * w, uy = dy / len * 0.5 * w;
        cairo_move_to(cr, a[0] - ux + uy, a[1] - uy - ux);
        cairo_line_to(cr, b[0] + ux + uy, b[1] + uy - ux);
        cairo_line_to(cr, b[0] + ux - uy, b[1] + uy + ux);
        cairo_line_to(cr, a[0] - ux - uy, a[1] - uy + ux);
        cairo_close_path(cr);
        cairo_fill(cr);
        continue;
      }
      cairo_move_to(cr, a[0], a[1]);
      cairo_line_to(cr, b[0], b[1]);
      cairo_set_line_width(cr, w);
      cairo_stroke(cr);
    }
  }
  cairo_restore(cr);
}

void draw_faces(cairo_t* cr, const View3& view, const std::vector<Face3>& faces) {
  FacePainter(view, faces).draw(cr, [](const Face3& f, Rgb& fill) {
    fill = f.fill;
    return true;
  });
}

}  // namespace kerfab
