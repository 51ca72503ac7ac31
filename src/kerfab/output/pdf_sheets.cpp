#include "kerfab/output/pdf_sheets.h"

#include <cairo-pdf.h>
#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "kerfab/core/errors.h"
#include "kerfab/output/sheet_files.h"

namespace kerfab {
namespace {

/// Draws one sheet in millimetres (the caller scales), y up as in the layout.
/// #rrggbb -> (r, g, b) in [0, 1]; the style was checked when the options were read.
std::array<double, 3> rgb(const std::string& hex) {
  const unsigned v = static_cast<unsigned>(std::stoul(hex.substr(1), nullptr, 16));
  return {((v >> 16) & 255) / 255.0, ((v >> 8) & 255) / 255.0, (v & 255) / 255.0};
}

void draw_sheet(cairo_t* cr, const std::vector<PlacedPart>& parts, const SheetStyle& style,
                double height, double line_mm) {
  const auto cut = rgb(style.cut), engrave = rgb(style.engrave);
  const auto mountain = rgb(style.mountain), valley = rgb(style.valley);
  auto move = [&](const Vec2& q) { cairo_move_to(cr, q.x(), height - q.y()); };
  auto line = [&](const Vec2& q) { cairo_line_to(cr, q.x(), height - q.y()); };
  cairo_set_line_width(cr, line_mm);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (const PlacedPart& p : parts) {
    if (!p.engraving.empty()) {
      cairo_set_source_rgb(cr, engrave[0], engrave[1], engrave[2]);
      for (const auto& s : p.engraving) {
        move(s[0]);
        line(s[1]);
      }
      cairo_stroke(cr);
    }
    for (const PlacedFold& f : p.folds) {
      const auto& c = f.mountain ? mountain : valley;
      cairo_set_source_rgb(cr, c[0], c[1], c[2]);
      if (f.mountain)
        cairo_set_dash(cr, kMountainDash.data(), static_cast<int>(kMountainDash.size()), 0);
      else
        cairo_set_dash(cr, kValleyDash.data(), static_cast<int>(kValleyDash.size()), 0);
      for (std::size_t i = 0; i < f.points.size(); ++i)
        i == 0 ? move(f.points[i]) : line(f.points[i]);
      cairo_stroke(cr);
      cairo_set_dash(cr, nullptr, 0, 0);
    }
    cairo_set_source_rgb(cr, cut[0], cut[1], cut[2]);
    for (const auto& c : p.kerf) {
      move(c[0]);
      line(c[1]);
    }
    for (std::size_t i = 0; i < p.outline.size(); ++i)
      i == 0 ? move(p.outline[i]) : line(p.outline[i]);
    cairo_close_path(cr);
    cairo_stroke(cr);
  }
}

/// The longest side of a sheet's PNG preview [px] (a 600 mm sheet at 2.5 px/mm is 1500).
constexpr double kMaxPreviewPixels = 4000;

void check(cairo_status_t status, const std::string& what) {
  if (status == CAIRO_STATUS_NO_MEMORY) throw std::bad_alloc();  // the machine's limit, not I/O
  if (status != CAIRO_STATUS_SUCCESS)
    throw IoError("cannot write " + what + ": " + cairo_status_to_string(status));
}

}  // namespace

void write_pdf_sheets(const RunResult& run, const SheetStyle& style,
                      const std::filesystem::path& cut_dir) {
  const double pt = 72.0 / 25.4;  // PDF points per mm
  for (int sheet = 0; sheet < run.layout->sheets; ++sheet) {
    const double w = run.layout->sheet_size(sheet).x(), h = run.layout->sheet_size(sheet).y();
    const auto path = sheet_file(cut_dir, sheet, "pdf");
    cairo_surface_t* surface = cairo_pdf_surface_create(path.c_str(), w * pt, h * pt);
    cairo_t* cr = cairo_create(surface);
    cairo_scale(cr, pt, pt);
    draw_sheet(cr, sheet_parts(run, sheet), style, h, style.stroke);
    cairo_show_page(cr);
    const cairo_status_t status = cairo_status(cr);
    cairo_destroy(cr);
    cairo_surface_finish(surface);
    const cairo_status_t surface_status = cairo_surface_status(surface);
    cairo_surface_destroy(surface);
    check(status, path.string());
    check(surface_status, path.string());
  }
}

void write_sheet_previews(const RunResult& run, const SheetStyle& style,
                          const std::filesystem::path& cut_dir, double pixels_per_mm) {
  const int sheets = run.layout->sheets;
  // The contact sheet's cells fit the largest sheet (offcuts may be smaller or larger).
  double w = run.options.layout.sheet_width, h = run.options.layout.sheet_height;
  if (sheets > 0) w = 0, h = 0;
  for (int sheet = 0; sheet < sheets; ++sheet)
    w = std::max(w, run.layout->sheet_size(sheet).x()),
    h = std::max(h, run.layout->sheet_size(sheet).y());
  // Contact sheet: about as many columns as rows, each sheet 500 px wide up to three columns,
  // smaller beyond, so that hundreds of sheets still make a picture of a few thousand pixels.
  const int columns =
      std::max(1, std::max(std::min(3, sheets), static_cast<int>(std::ceil(std::sqrt(sheets)))));
  const int rows = std::max(1, (sheets + columns - 1) / columns);
  const double thumb = std::min(500.0, 3000.0 / columns) / w;  // pixels per mm in the contact sheet
  const int tw = static_cast<int>(std::ceil(w * thumb)),
            th = static_cast<int>(std::ceil(h * thumb));
  // Each sheet's number goes in a band above its cell, outside the sheet: drawn on the sheet
  // at 20 mm it covered parts of small offcuts.
  constexpr int kGap = 20, kBand = 30;
  cairo_surface_t* contact = cairo_image_surface_create(
      CAIRO_FORMAT_RGB24, columns * (tw + kGap) + kGap, rows * (th + kBand) + kGap);
  cairo_t* cc = cairo_create(contact);
  cairo_set_source_rgb(cc, 0.85, 0.85, 0.85);
  cairo_paint(cc);
  for (int sheet = 0; sheet < sheets; ++sheet) {
    const std::vector<PlacedPart> parts = sheet_parts(run, sheet);
    const double sw = run.layout->sheet_size(sheet).x(), sh = run.layout->sheet_size(sheet).y();
    // At most kMaxPreviewPixels on its long side: a 10 m sheet at 2.5 px/mm was a 2.5 GB image.
    const double scale = std::min(pixels_per_mm, kMaxPreviewPixels / std::max(sw, sh));
    const int pw = static_cast<int>(std::ceil(sw * scale));
    const int ph = static_cast<int>(std::ceil(sh * scale));
    cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, pw, ph);
    cairo_t* cr = cairo_create(surface);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_scale(cr, scale, scale);
    draw_sheet(cr, parts, style, sh, 0.4);
    cairo_destroy(cr);
    const auto path = sheet_file(cut_dir, sheet, "png");
    check(cairo_surface_write_to_png(surface, path.c_str()), path.string());
    cairo_surface_destroy(surface);
    // The same sheet, small, on the contact sheet.
    cairo_save(cc);
    cairo_translate(cc, kGap + (sheet % columns) * (tw + kGap),
                    kBand + (sheet / columns) * (th + kBand));
    // The sheet's number, 14 px tall, in the band above the sheet's top left corner.
    Label number;
    number.text = std::to_string(sheet + 1);
    number.height = 14;
    number.origin = Vec2(0, 8);
    cairo_set_source_rgb(cc, 0.2, 0.2, 0.2);
    cairo_set_line_width(cc, 2);
    for (const auto& stroke : label_strokes(number)) {
      cairo_move_to(cc, stroke[0].x(), -stroke[0].y());
      cairo_line_to(cc, stroke[1].x(), -stroke[1].y());
    }
    cairo_stroke(cc);
    cairo_rectangle(cc, 0, 0, std::ceil(sw * thumb), std::ceil(sh * thumb));
    cairo_set_source_rgb(cc, 1, 1, 1);
    cairo_fill(cc);
    cairo_scale(cc, thumb, thumb);
    draw_sheet(cc, parts, style, sh, 0.8);
    cairo_restore(cc);
  }
  cairo_destroy(cc);
  std::error_code ec;
  std::filesystem::create_directories(cut_dir, ec);
  const auto path = cut_dir / "contact-sheet.png";
  check(cairo_surface_write_to_png(contact, path.c_str()), path.string());
  cairo_surface_destroy(contact);
}

}  // namespace kerfab
