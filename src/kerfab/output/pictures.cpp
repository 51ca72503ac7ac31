#include "kerfab/output/pictures.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "kerfab/core/errors.h"
#include "kerfab/output/cairo_picture.h"
#include "kerfab/output/strip_files.h"

namespace kerfab {
namespace fs = std::filesystem;
namespace {

Rgb rgb(const std::array<int, 3>& c) { return {c[0] / 255.0, c[1] / 255.0, c[2] / 255.0}; }

void write_png(cairo_surface_t* s, const fs::path& path) {
  cairo_surface_flush(s);
  if (cairo_surface_write_to_png(s, path.c_str()) != CAIRO_STATUS_SUCCESS)
    throw IoError("cannot write " + path.string());
}

/// A 3D picture of \p faces, \p width pixels wide and as high as the view needs.
void picture_3d(const std::vector<Face3>& faces, const PictureOptions& o, const fs::path& path) {
  const std::vector<Vec3> corners = corners_of(faces);
  if (corners.empty()) return;
  const int w = o.width_3d;
  const int h = static_cast<int>(std::ceil(w * std::min(2.0, View3::aspect(corners, o.view))));
  auto [surface, cr] = white_picture(w, h);
  draw_faces(cr.get(), View3(corners, o.view, 0, 0, w, h), faces);
  write_png(surface.get(), path);
}

/// The edge (sorted vertex pair) -> the faces that use it.
std::map<std::pair<int, int>, std::vector<int>> edge_faces(
    const std::vector<std::array<int, 4>>& faces) {
  std::map<std::pair<int, int>, std::vector<int>> out;
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 4; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % 4];
      out[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(f));
    }
  return out;
}

std::vector<Face3> bending_faces(const PolyMesh& quads, const BendingResult& bending) {
  std::vector<Face3> out;
  for (auto f : quads.faces()) {
    Face3 face;
    face.fill = {0.98, 0.98, 0.95};
    int k = 0;
    for (auto h : quads.fh_range(f)) {
      face.corners.push_back(to_eigen(quads.point(quads.from_vertex_handle(h))));
      const bool bend = bending.bendable[quads.edge_handle(h).idx()] != 0;
      face.sides.push_back(bend ? SideStroke{k, {0.82, 0.06, 0.06}, 2.0, 1.0}
                                : SideStroke{k, {0.33, 0.33, 0.33}, 0.4, 1.0});
      ++k;
    }
    out.push_back(std::move(face));
  }
  return out;
}

/// A flat shape for the stacked pictures: polygons and segments in its principal frame.
struct FlatShape {
  std::string label;
  std::vector<std::pair<Polygon2, Rgb>> fills;                        ///< filled, no stroke
  std::vector<std::tuple<Vec2, Vec2, Rgb, double>> lines;             ///< a, b, colour, width
  std::vector<std::tuple<Polygon2, Rgb, double>> outlines;            ///< closed, stroked
};

/// Turns every point of \p shape so that its principal direction is horizontal, centred.
void principal_frame(FlatShape& shape) {
  std::vector<Vec2*> pts;
  for (auto& [poly, c] : shape.fills)
    for (auto& p : poly) pts.push_back(&p);
  for (auto& [a, b, c, w] : shape.lines) pts.insert(pts.end(), {&a, &b});
  for (auto& [poly, c, w] : shape.outlines)
    for (auto& p : poly) pts.push_back(&p);
  if (pts.empty()) return;
  Vec2 mean = Vec2::Zero();
  for (const Vec2* p : pts) mean += *p;
  mean /= static_cast<double>(pts.size());
  double sxx = 0, syy = 0, sxy = 0;
  for (const Vec2* p : pts) {
    const Vec2 d = *p - mean;
    sxx += d.x() * d.x();
    syy += d.y() * d.y();
    sxy += d.x() * d.y();
  }
  const Eigen::Rotation2Dd turn(-0.5 * std::atan2(2 * sxy, sxx - syy));
  for (Vec2* p : pts) *p = turn * (*p - mean);
}

/// Shapes stacked top to bottom at one scale (the widest fills the picture less 80 px), each
/// numbered on the left.
void picture_stacked(std::vector<FlatShape> shapes, int width, const fs::path& path) {
  if (shapes.empty()) return;
  struct Box {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    void add(const Vec2& p) {
      x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x());
      y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
    }
  };
  std::vector<Box> boxes;
  double widest = 1e-9;
  for (FlatShape& s : shapes) {
    principal_frame(s);
    Box b;
    for (const auto& [poly, c] : s.fills)
      for (const auto& p : poly) b.add(p);
    for (const auto& [a, e, c, w] : s.lines) b.add(a), b.add(e);
    for (const auto& [poly, c, w] : s.outlines)
      for (const auto& p : poly) b.add(p);
    if (b.x1 < b.x0) b = {0, 1, 0, 1};
    widest = std::max(widest, b.x1 - b.x0);
    boxes.push_back(b);
  }
  const double scale = (width - 80) / widest;
  double height = 30;
  for (const Box& b : boxes) height += scale * (b.y1 - b.y0) + 16;
  auto [surface, cr] = white_picture(width, static_cast<int>(std::ceil(height)));
  cairo_t* c = cr.get();
  cairo_set_line_join(c, CAIRO_LINE_JOIN_ROUND);
  double y = 20;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const Box& b = boxes[i];
    auto P = [&](const Vec2& q) {
      return std::array<double, 2>{60 + scale * (q.x() - b.x0), y + scale * (b.y1 - q.y())};
    };
    auto path_of = [&](const Polygon2& poly) {
      for (std::size_t k = 0; k < poly.size(); ++k) {
        const auto p = P(poly[k]);
        k == 0 ? cairo_move_to(c, p[0], p[1]) : cairo_line_to(c, p[0], p[1]);
      }
      cairo_close_path(c);
    };
    for (const auto& [poly, colour] : shapes[i].fills) {
      path_of(poly);
      cairo_set_source_rgb(c, colour[0], colour[1], colour[2]);
      cairo_fill(c);
    }
    for (const auto& [a, e, colour, w] : shapes[i].lines) {
      const auto pa = P(a), pe = P(e);
      cairo_move_to(c, pa[0], pa[1]);
      cairo_line_to(c, pe[0], pe[1]);
      cairo_set_source_rgb(c, colour[0], colour[1], colour[2]);
      cairo_set_line_width(c, w);
      cairo_stroke(c);
    }
    for (const auto& [poly, colour, w] : shapes[i].outlines) {
      path_of(poly);
      cairo_set_source_rgb(c, colour[0], colour[1], colour[2]);
      cairo_set_line_width(c, w);
      cairo_stroke(c);
    }
    cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(c, 14);
    cairo_set_source_rgb(c, 0, 0, 0);
    cairo_move_to(c, 6, y + scale * (b.y1 - b.y0) / 2 + 5);
    cairo_show_text(c, shapes[i].label.c_str());
    y += scale * (b.y1 - b.y0) + 16;
  }
  write_png(surface.get(), path);
}

std::string three_digits(int n) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%03d", n);
  return buf;
}

/// The six largest flattened ladder patches (all patches if none is a ladder).
std::vector<FlatShape> patch_shapes(const Strips& strips, const Flattening& flat) {
  std::vector<std::pair<double, int>> by_area;
  for (std::size_t p = 0; p < strips.patches.size() && p < flat.patches.size(); ++p) {
    const Patch& patch = strips.patches[p];
    const auto quads = patch.local_quads();  // facets too
    double area = 0;
    for (const auto& q : quads) {
      Polygon2 poly;
      for (int v : q) poly.push_back(flat.patches[p].points[v]);
      area += std::abs(polygon_area(poly));
    }
    by_area.push_back({patch.flat ? -1 / (1 + area) : area, static_cast<int>(p)});
  }
  std::stable_sort(by_area.begin(), by_area.end(), std::greater<>());
  std::vector<FlatShape> out;
  for (std::size_t k = 0; k < by_area.size() && k < 6; ++k) {
    const int p = by_area[k].second;
    const Patch& patch = strips.patches[p];
    const auto quads = patch.local_quads();  // facets too
    std::map<std::pair<int, int>, int> uses;
    for (const auto& q : quads)
      for (int i = 0; i < 4; ++i) ++uses[{std::min(q[i], q[(i + 1) % 4]), std::max(q[i], q[(i + 1) % 4])}];
    FlatShape s;
    s.label = three_digits(p);
    const auto& pts = flat.patches[p].points;
    for (const auto& [e, n] : uses) {
      if (n == 1) continue;
      s.lines.emplace_back(pts[e.first], pts[e.second], Rgb{0.5, 0.5, 0.5}, 0.4);
    }
    for (const auto& [e, n] : uses)
      if (n == 1) s.lines.emplace_back(pts[e.first], pts[e.second], Rgb{0.75, 0, 0}, 1.2);
    out.push_back(std::move(s));
  }
  return out;
}

/// The three parts with the most teeth, as cut: laser path, kerf cuts, tooth regions.
std::vector<FlatShape> part_shapes(const Joints& joints, const KerfResult& kerf) {
  std::vector<std::pair<int, int>> by_teeth;
  for (std::size_t p = 0; p < joints.parts.size(); ++p) {
    int teeth = 0;
    for (const JointSpan& s : joints.parts[p].spans) teeth += s.tooth ? 1 : 0;
    by_teeth.push_back({teeth, -static_cast<int>(p)});
  }
  std::stable_sort(by_teeth.begin(), by_teeth.end(), std::greater<>());
  std::vector<FlatShape> out;
  for (std::size_t k = 0; k < by_teeth.size() && k < 3; ++k) {
    const int p = -by_teeth[k].second;
    FlatShape s;
    s.label = three_digits(p);
    for (const JointSpan& span : joints.parts[p].spans)
      if (span.tooth && span.region.size() >= 3)
        s.fills.emplace_back(span.region, Rgb{0.61, 0.77, 0.94});
    if (p < static_cast<int>(kerf.patches.size()))
      for (const KerfCut& cut : kerf.patches[p].cuts)
        s.lines.emplace_back(cut.a, cut.b, Rgb{0.19, 0.19, 0.19}, 0.5);
    s.outlines.emplace_back(joints.parts[p].cut, Rgb{0.82, 0, 0}, 0.8);
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace

std::vector<Face3> strip_faces(const Strips& strips, const std::vector<Rgb>& colour) {
  const auto uses = edge_faces(strips.faces);
  std::vector<Face3> out;
  out.reserve(strips.faces.size());
  for (std::size_t f = 0; f < strips.faces.size(); ++f) {
    Face3 face;
    const int patch = strips.face_patch[f];
    face.fill = colour.empty() ? rgb(strip_colour(patch)) : colour[f];
    for (int k = 0; k < 4; ++k) {
      const int a = strips.faces[f][k], b = strips.faces[f][(k + 1) % 4];
      face.corners.push_back(strips.vertices[a]);
      const auto& users = uses.at({std::min(a, b), std::max(a, b)});
      bool border = users.size() < 2;
      for (int g : users) border = border || strips.face_patch[g] != patch;
      face.sides.push_back(border ? SideStroke{k, {0.13, 0.13, 0.13}, 1.3, 1.0}
                                  : SideStroke{k, {0.24, 0.24, 0.24}, 0.4, 0.35});
    }
    out.push_back(std::move(face));
  }
  return out;
}

std::vector<Face3> coarse_strip_faces(const Strips& strips) {
  const auto uses = edge_faces(strips.faces);
  std::map<int, std::vector<int>> by_quad;
  for (std::size_t f = 0; f < strips.faces.size(); ++f)
    by_quad[strips.face_quad[f]].push_back(static_cast<int>(f));
  std::vector<Face3> out;
  for (const auto& [quad, group] : by_quad) {
    // The group's boundary: its directed edges whose reverse is not in the group, chained.
    std::map<std::pair<int, int>, int> directed;
    for (int f : group)
      for (int k = 0; k < 4; ++k) ++directed[{strips.faces[f][k], strips.faces[f][(k + 1) % 4]}];
    std::map<int, int> next;
    bool simple = true;
    for (const auto& [e, count] : directed)
      if (!directed.count({e.second, e.first}))
        simple = simple && count == 1 && next.emplace(e.first, e.second).second;
    std::vector<int> loop;
    if (simple && !next.empty()) {
      int v = next.begin()->first;
      do {
        loop.push_back(v);
        const auto it = next.find(v);
        if (it == next.end()) break;
        v = it->second;
      } while (v != loop.front() && loop.size() <= next.size());
      simple = v == loop.front() && loop.size() == next.size();
    }
    const int patch = strips.face_patch[group.front()];
    if (!simple) {  // not a disk: the sub-quads as they are
      for (int f : group) {
        Face3 face;
        face.fill = rgb(strip_colour(patch));
        face.tag = patch;
        for (int v : strips.faces[f]) face.corners.push_back(strips.vertices[v]);
        out.push_back(std::move(face));
      }
      continue;
    }
    Face3 face;
    face.fill = rgb(strip_colour(patch));
    face.tag = patch;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      face.corners.push_back(strips.vertices[a]);
      const auto& users = uses.at({std::min(a, b), std::max(a, b)});
      bool border = users.size() < 2;
      for (int g : users) border = border || strips.face_patch[g] != patch;
      if (border) face.sides.push_back({static_cast<int>(k), {0.13, 0.13, 0.13}, 0.8, 1.0});
    }
    out.push_back(std::move(face));
  }
  return out;
}

void write_pictures(const RunResult& run, const PictureOptions& o, const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError("cannot create directory " + dir.string() + ": " + ec.message());
  if (run.bending && run.input)
    picture_3d(bending_faces(run.input->quads, *run.bending), o, dir / "bending.png");
  if (run.strips) picture_3d(strip_faces(run.final_strips()), o, dir / "strips.png");
  if (run.kerf) {
    const FaceDensity d = kerf_density(run.final_strips(), *run.kerf);
    std::vector<Rgb> colour;
    for (const auto& c : d.colour) colour.push_back(rgb(c));
    picture_3d(strip_faces(run.final_strips(), colour), o, dir / "kerf_density.png");
  }
  if (run.flat)
    picture_stacked(patch_shapes(run.flat->strips, run.flat->flattening), o.width_flat,
                    dir / "patches.png");
  if (run.joints && run.kerf)
    picture_stacked(part_shapes(*run.joints, *run.kerf), o.width_flat, dir / "parts.png");
}

}  // namespace kerfab
