#include "kerfab/output/assembly_guide.h"

#include <cairo-pdf.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "kerfab/core/errors.h"
#include "kerfab/output/cairo_picture.h"
#include "kerfab/output/pictures.h"
#include "kerfab/output/render3d.h"
#include "kerfab/output/sheet_files.h"
#include "kerfab/output/strip_files.h"

// The page and the three.js files it uses are built into kerfab (GNU as .incbin), so a run
// writes them beside the page and it opens with no server and no network. three.js comes from
// Debian's libjs-three (CMake checks its revision); the page's own files from guide/.
#define KERFAB_EMBED(name, file)                                                    \
  __asm__(".section .rodata\n.balign 16\n.global " #name "_begin\n.hidden " #name \
          "_begin\n" #name "_begin:\n.incbin \"" file "\"\n.global " #name          \
          "_end\n.hidden " #name "_end\n" #name "_end:\n.byte 0\n.previous\n");     \
  extern "C" const char name##_begin[], name##_end[];

KERFAB_EMBED(kerfab_three_js, KERFAB_THREE_JS)
KERFAB_EMBED(kerfab_orbit_controls_js, KERFAB_ORBIT_CONTROLS_JS)
KERFAB_EMBED(kerfab_guide_html, KERFAB_GUIDE_DIR "/index.html")
KERFAB_EMBED(kerfab_guide_js, KERFAB_GUIDE_DIR "/guide.js")

namespace kerfab {
namespace fs = std::filesystem;
using nlohmann::json;
namespace {

std::string_view embedded(const char* begin, const char* end) {
  return {begin, static_cast<std::size_t>(end - begin)};
}

double round2(double x) { return std::round(x * 100) / 100; }

std::string hex_colour(const std::array<int, 3>& c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c[0], c[1], c[2]);
  return buf;
}

json contact_json(const PartContact& c) {
  return json::array({c.part, round2(c.length), round2(c.toothed)});
}

/// Sub-quad normal (cross product of its diagonals), unit.
Vec3 face_normal(const Strips& s, const std::array<int, 4>& q) {
  const Vec3 n = (s.vertices[q[2]] - s.vertices[q[0]]).cross(s.vertices[q[3]] - s.vertices[q[1]]);
  return n.norm() > 0 ? n.normalized() : Vec3::UnitZ();
}

/// The data the page shows, as JSON.
json model_json(const RunResult& run) {
  const Strips& strips = run.final_strips();
  const int parts = static_cast<int>(strips.patches.size());
  const AssemblyPlan& plan = *run.assembly;
  const LayoutResult& layout = *run.layout;
  const double diagonal = bounding_box(triangulate(strips)).diagonal();
  // Per part: its sub-quads.
  std::vector<std::vector<int>> faces(parts);
  for (std::size_t f = 0; f < strips.faces.size(); ++f) faces[strips.face_patch[f]].push_back(f);
  std::vector<int> step_of(parts, -1);
  for (std::size_t k = 0; k < plan.steps.size(); ++k) step_of[plan.steps[k].part] = k;
  json jparts = json::array();
  for (int p = 0; p < parts; ++p) {
    std::map<int, int> local;  // strip vertex -> index in this part
    json pos = json::array(), tri = json::array(), edges = json::array();
    auto index = [&](int v) {
      const auto [it, added] = local.emplace(v, static_cast<int>(local.size()));
      if (added)
        for (int k = 0; k < 3; ++k) pos.push_back(round2(strips.vertices[v][k]));
      return it->second;
    };
    std::map<std::pair<int, int>, int> uses;
    Vec3 centre = Vec3::Zero();
    for (int f : faces[p]) {
      const auto& q = strips.faces[f];
      for (int k = 0; k < 4; ++k) {
        ++uses[{std::min(q[k], q[(k + 1) % 4]), std::max(q[k], q[(k + 1) % 4])}];
        centre += strips.vertices[q[k]] / 4.0;
      }
      const int a = index(q[0]), b = index(q[1]), c = index(q[2]), d = index(q[3]);
      tri.insert(tri.end(), {a, b, c, a, c, d});
    }
    if (!faces[p].empty()) centre /= static_cast<double>(faces[p].size());
    for (const auto& [e, n] : uses)
      if (n == 1)
        for (int v : {e.first, e.second})
          for (int k = 0; k < 3; ++k) edges.push_back(round2(strips.vertices[v][k]));
    // The label sits over the sub-quad nearest the part's centre, a little off the surface.
    Vec3 label = centre;
    double best = 1e300;
    for (int f : faces[p]) {
      Vec3 m = Vec3::Zero();
      for (int v : strips.faces[f]) m += strips.vertices[v] / 4.0;
      if ((m - centre).norm() < best) {
        best = (m - centre).norm();
        label = m + 0.012 * diagonal * face_normal(strips, strips.faces[f]);
      }
    }
    json neighbours = json::array();
    for (const PartContact& c : plan.contacts[p]) neighbours.push_back(contact_json(c));
    jparts.push_back({{"n", p},
                      {"sheet", layout.sheet_number(p)},
                      {"step", step_of[p] + 1},
                      {"colour", hex_colour(strip_colour(p))},
                      {"area", round2(std::abs(polygon_area(run.joints->parts[p].designed)))},
                      {"pos", pos},
                      {"tri", tri},
                      {"edges", edges},
                      {"label", {round2(label.x()), round2(label.y()), round2(label.z())}},
                      {"neighbours", neighbours}});
  }
  json steps = json::array();
  for (const AssemblyStep& s : plan.steps) {
    json joins = json::array();
    for (const PartContact& c : s.joins) joins.push_back(contact_json(c));
    steps.push_back({{"part", s.part},
                     {"joins", joins},
                     {"held", round2(s.held)},
                     {"closing", s.closing},
                     {"new_piece", s.new_piece}});
  }
  json sheets = json::array();
  for (int s = 0; s < layout.sheets; ++s) {
    json on = json::array();
    for (const PlacedPart& placed : sheet_parts(run, s)) {
      json outline = json::array();
      for (const Vec2& v : placed.outline) outline.insert(outline.end(), {round2(v.x()), round2(v.y())});
      on.push_back({{"part", placed.part}, {"outline", outline}});
    }
    sheets.push_back({{"n", s + 1},
                      {"w", layout.sheet_size(s).x()},
                      {"h", layout.sheet_size(s).y()},
                      {"parts", on}});
  }
  return {{"version", 1},
          {"units", "mm"},
          {"model", run.inputs.target.filename().string()},
          {"diagonal", round2(diagonal)},
          {"rule", kAssemblyRule},
          // What holds a border: box teeth and dovetail tabs, or (paper) glue tabs.
          {"joint", run.joints && run.joints->glue_tabs > 0 ? "glue tabs" : "teeth or tabs"},
          {"pieces", plan.pieces},
          {"parts", jparts},
          {"steps", steps},
          {"sheets", sheets}};
}

/// steps.pdf: A4 pages of 4 x 5 steps; each a picture of the parts placed so far (grey), the
/// new one orange, and a caption: step, part, sheet, the parts it joins.
void write_steps_pdf(const RunResult& run, const fs::path& path) {
  const Strips& strips = run.final_strips();
  const AssemblyPlan& plan = *run.assembly;
  const std::vector<Face3> all = coarse_strip_faces(strips);
  const std::vector<Vec3> corners = corners_of(all);
  if (corners.empty() || plan.steps.empty()) return;
  const ViewOptions view;
  const double page_w = 595.276, page_h = 841.89;  // A4 [pt]
  const int cols = 4, rows = 5;
  const double margin = 36, cell_w = (page_w - 2 * margin) / cols,
               cell_h = (page_h - 2 * margin - 24) / rows, caption = 30;
  const double px = 1.5;  // picture pixels per point (216 dpi)
  CairoSurface pdf(cairo_pdf_surface_create(path.c_str(), page_w, page_h),
                   cairo_surface_destroy);
  if (cairo_surface_status(pdf.get()) != CAIRO_STATUS_SUCCESS)
    throw IoError("cannot write " + path.string());
  cairo_pdf_surface_set_metadata(pdf.get(), CAIRO_PDF_METADATA_TITLE, "kerfab assembly steps");
  CairoContext cr(cairo_create(pdf.get()), cairo_destroy);
  cairo_t* c = cr.get();
  const int pic_w = static_cast<int>(cell_w * px), pic_h = static_cast<int>((cell_h - caption) * px);
  // The step pictures are drawn at twice the size, faces added part by part as they are
  // placed (steps times faces would grow with the square of the model), and scaled down.
  const int ss = 2;
  const FacePainter painter(View3(corners, view, 0, 0, ss * pic_w, ss * pic_h), all);
  LayeredPicture layers(painter, ss * pic_w, ss * pic_h, ss);
  const std::size_t per_page = cols * rows;
  for (std::size_t k = 0; k < plan.steps.size(); ++k) {
    const AssemblyStep& step = plan.steps[k];
    const std::size_t slot = k % per_page;
    if (slot == 0) {
      if (k > 0) cairo_show_page(c);
      cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
      cairo_set_font_size(c, 11);
      cairo_set_source_rgb(c, 0, 0, 0);
      cairo_move_to(c, margin, margin);
      const std::string title = "kerfab assembly: steps " + std::to_string(k + 1) + " to " +
                                std::to_string(std::min(k + per_page, plan.steps.size())) +
                                " of " + std::to_string(plan.steps.size()) +
                                " (new part orange, joined parts darker)";
      cairo_show_text(c, title.c_str());
    }
    std::vector<char> joined(strips.patches.size(), 0);
    for (const PartContact& j : step.joins) joined[j.part] = 1;
    layers.add(step.part);
    auto [big, bc] = white_picture(ss * pic_w, ss * pic_h);
    layers.paint(big.get(), [&](int p) {
      return p == step.part ? Rgb{1.0, 0.5, 0.05}
             : joined[p]    ? Rgb{0.62, 0.66, 0.75}
                            : Rgb{0.88, 0.88, 0.88};
    });
    bc.reset();
    auto [image, ic] = white_picture(pic_w, pic_h);
    cairo_scale(ic.get(), 1.0 / ss, 1.0 / ss);
    cairo_set_source_surface(ic.get(), big.get(), 0, 0);
    cairo_pattern_set_filter(cairo_get_source(ic.get()), CAIRO_FILTER_GOOD);
    cairo_paint(ic.get());
    ic.reset();
    cairo_surface_flush(image.get());
    const double x = margin + (slot % cols) * cell_w;
    const double y = margin + 12 + (slot / cols) * cell_h;
    cairo_save(c);
    cairo_translate(c, x, y);
    cairo_scale(c, 1 / px, 1 / px);
    cairo_set_source_surface(c, image.get(), 0, 0);
    cairo_paint(c);
    cairo_restore(c);
    cairo_rectangle(c, x + 2, y, cell_w - 4, cell_h - 4);
    cairo_set_source_rgb(c, 0.8, 0.8, 0.8);
    cairo_set_line_width(c, 0.5);
    cairo_stroke(c);
    const int sheet = run.layout->sheet_number(step.part);
    std::string line1 = "Step " + std::to_string(k + 1) + ": part " + std::to_string(step.part) +
                        (sheet > 0 ? ", sheet " + std::to_string(sheet) : ", on no sheet");
    std::string line2 = step.new_piece ? (k == 0 ? "start here" : "starts a separate piece")
                                       : "joins ";
    if (!step.new_piece)
      for (std::size_t j = 0; j < step.joins.size(); ++j) {
        if (j == 4) {
          line2 += " +" + std::to_string(step.joins.size() - 4);
          break;
        }
        line2 += (j ? ", " : "") + std::to_string(step.joins[j].part);
      }
    if (step.closing) line2 += " (fills a hole)";
    cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_font_size(c, 8);
    cairo_set_source_rgb(c, 0, 0, 0);
    cairo_move_to(c, x + 6, y + cell_h - caption + 6);
    cairo_show_text(c, line1.c_str());
    cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_move_to(c, x + 6, y + cell_h - caption + 18);
    cairo_show_text(c, line2.c_str());
  }
  cairo_show_page(c);
  cr.reset();
  cairo_surface_finish(pdf.get());
  if (cairo_surface_status(pdf.get()) != CAIRO_STATUS_SUCCESS)
    throw IoError("cannot write " + path.string());
}

}  // namespace

void write_assembly_guide(const RunResult& run, const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError("cannot create directory " + dir.string() + ": " + ec.message());
  write_text_file(dir / "three.min.js",
                  std::string(embedded(kerfab_three_js_begin, kerfab_three_js_end)));
  write_text_file(dir / "OrbitControls.js", std::string(embedded(kerfab_orbit_controls_js_begin,
                                                                 kerfab_orbit_controls_js_end)));
  write_text_file(dir / "guide.js",
                  std::string(embedded(kerfab_guide_js_begin, kerfab_guide_js_end)));
  write_text_file(dir / "index.html",
                  std::string(embedded(kerfab_guide_html_begin, kerfab_guide_html_end)));
  write_text_file(dir / "model.js",
                  "// kerfab assembly guide data (mm)\nwindow.KERFAB_MODEL = " +
                      model_json(run).dump(-1, ' ', false, json::error_handler_t::replace) +
                      ";\n");
  write_steps_pdf(run, dir / "steps.pdf");
}

}  // namespace kerfab
