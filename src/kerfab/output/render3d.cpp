#include "kerfab/output/render3d.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

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

void FacePainter::draw(cairo_t* cr) const {
  cairo_save(cr);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (const Drawn& d : order_) {
    const Face3& f = faces_[d.face];
    const Rgb& colour = f.fill;
    const auto* s = screen_.data() + d.first;
    const std::size_t n = f.corners.size();
    cairo_move_to(cr, s[0][0], s[0][1]);
    for (std::size_t k = 1; k < n; ++k) cairo_line_to(cr, s[k][0], s[k][1]);
    cairo_close_path(cr);
    cairo_set_source_rgb(cr, colour[0] * d.shade, colour[1] * d.shade, colour[2] * d.shade);
    cairo_fill_preserve(cr);
    cairo_set_line_width(cr, 0.6);  // closes the hairline gaps between neighbouring faces
    cairo_stroke(cr);
    for (const SideStroke& side : f.sides) {
      const auto& a = s[side.side % n];
      const auto& b = s[(side.side + 1) % n];
      cairo_move_to(cr, a[0], a[1]);
      cairo_line_to(cr, b[0], b[1]);
      cairo_set_source_rgba(cr, side.colour[0], side.colour[1], side.colour[2], side.opacity);
      cairo_set_line_width(cr, side.width);
      cairo_stroke(cr);
    }
  }
  cairo_restore(cr);
}

LayeredPicture::LayeredPicture(const FacePainter& painter, int w, int h, double line_scale)
    : painter_(painter),
      w_(std::max(w, 1)),
      h_(std::max(h, 1)),
      line_scale_(line_scale),
      top_(static_cast<std::size_t>(w_) * static_cast<std::size_t>(h_), -1) {
  const auto& order = painter.far_to_near();
  std::vector<double> sizes;  // square roots of the faces' areas on the picture
  for (const auto& d : order) {
    const auto* p = painter.screen().data() + d.first;
    const std::size_t n = painter.faces()[d.face].corners.size();
    double area = 0;
    for (std::size_t k = 0; k < n; ++k)
      area += p[k][0] * p[(k + 1) % n][1] - p[(k + 1) % n][0] * p[k][1];
    sizes.push_back(std::sqrt(0.5 * std::abs(area)));
  }
  if (!sizes.empty()) {
    std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
    widest_ = sizes[sizes.size() / 2] / 8;
  }
  int tags = 0;
  for (const auto& d : order) tags = std::max(tags, painter.faces()[d.face].tag + 1);
  by_tag_.resize(static_cast<std::size_t>(tags));
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Face3& f = painter.faces()[order[i].face];
    if (f.tag < 0) continue;
    for (int side = -1; side < static_cast<int>(f.sides.size()); ++side) {
      by_tag_[static_cast<std::size_t>(f.tag)].push_back(static_cast<int>(items_.size()));
      items_.push_back({i, side});
    }
  }
}

void LayeredPicture::fill_polygon(const std::vector<std::array<double, 2>>& p, int item) {
  // Pixel centres inside the polygon (even-odd), row by row: a pixel takes the item when it is
  // later in the painter's order than what the pixel shows.
  double y0 = p[0][1], y1 = p[0][1];
  for (const auto& q : p) y0 = std::min(y0, q[1]), y1 = std::max(y1, q[1]);
  const int r0 = std::max(0, static_cast<int>(std::ceil(y0 - 0.5)));
  const int r1 = std::min(h_ - 1, static_cast<int>(std::floor(y1 - 0.5)));
  std::vector<double> xs;
  for (int r = r0; r <= r1; ++r) {
    const double yc = r + 0.5;
    xs.clear();
    for (std::size_t k = 0, n = p.size(); k < n; ++k) {
      const auto &a = p[k], &b = p[(k + 1) % n];
      if ((a[1] <= yc) == (b[1] <= yc)) continue;
      xs.push_back(a[0] + (yc - a[1]) * (b[0] - a[0]) / (b[1] - a[1]));
    }
    std::sort(xs.begin(), xs.end());
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
      const int c0 = std::max(0, static_cast<int>(std::ceil(xs[k] - 0.5)));
      const int c1 = std::min(w_, static_cast<int>(std::ceil(xs[k + 1] - 0.5)));
      int* row = top_.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(w_);
      for (int c = c0; c < c1; ++c) row[c] = std::max(row[c], item);
    }
  }
}

void LayeredPicture::add(int tag) {
  if (tag < 0 || tag >= static_cast<int>(by_tag_.size())) return;
  std::vector<std::array<double, 2>> poly;
  for (int item : by_tag_[static_cast<std::size_t>(tag)]) {
    const Item& it = items_[static_cast<std::size_t>(item)];
    const FacePainter::Drawn& d = painter_.far_to_near()[it.drawn];
    const Face3& f = painter_.faces()[d.face];
    const auto* s = painter_.screen().data() + d.first;
    const std::size_t n = f.corners.size();
    poly.clear();
    if (it.side < 0) {
      poly.assign(s, s + n);
    } else {
      // The stroke as a bar with square ends, its width across the side.
      const SideStroke& side = f.sides[static_cast<std::size_t>(it.side)];
      const auto& a = s[static_cast<std::size_t>(side.side) % n];
      const auto& b = s[static_cast<std::size_t>(side.side + 1) % n];
      const double dx = b[0] - a[0], dy = b[1] - a[1], len = std::hypot(dx, dy);
      if (!(len > 0)) continue;
      const double half =
          0.5 * std::clamp(widest_, 0.25 * side.width, line_scale_ * side.width);
      const double ux = dx / len * half, uy = dy / len * half;
      poly = {{a[0] - ux + uy, a[1] - uy - ux},
              {b[0] + ux + uy, b[1] + uy - ux},
              {b[0] + ux - uy, b[1] + uy + ux},
              {a[0] - ux - uy, a[1] - uy + ux}};
    }
    fill_polygon(poly, item);
  }
}

void LayeredPicture::paint(cairo_surface_t* image,
                           const std::function<Rgb(int tag)>& colour) const {
  cairo_surface_flush(image);
  unsigned char* data = cairo_image_surface_get_data(image);
  const int stride = cairo_image_surface_get_stride(image);
  const int w = std::min(w_, cairo_image_surface_get_width(image));
  const int h = std::min(h_, cairo_image_surface_get_height(image));
  if (!data) return;
  std::vector<Rgb> of_tag(by_tag_.size());
  for (std::size_t t = 0; t < by_tag_.size(); ++t) of_tag[t] = colour(static_cast<int>(t));
  auto byte = [](double v) {
    return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255));
  };
  for (int r = 0; r < h; ++r) {
    auto* out = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(r) * stride);
    const int* row = top_.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(w_);
    for (int c = 0; c < w; ++c) {
      Rgb px{1, 1, 1};
      if (row[c] >= 0) {
        const Item& it = items_[static_cast<std::size_t>(row[c])];
        const FacePainter::Drawn& d = painter_.far_to_near()[it.drawn];
        const Face3& f = painter_.faces()[d.face];
        if (it.side < 0) {
          const Rgb& fill = of_tag[static_cast<std::size_t>(f.tag)];
          px = {fill[0] * d.shade, fill[1] * d.shade, fill[2] * d.shade};
        } else {
          px = f.sides[static_cast<std::size_t>(it.side)].colour;
        }
      }
      out[c] = 0xFF000000u | byte(px[0]) << 16 | byte(px[1]) << 8 | byte(px[2]);
    }
  }
  cairo_surface_mark_dirty(image);
}

void draw_faces(cairo_t* cr, const View3& view, const std::vector<Face3>& faces) {
  FacePainter(view, faces).draw(cr);
}

}  // namespace kerfab
