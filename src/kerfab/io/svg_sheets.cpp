#include "kerfab/io/svg_sheets.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "kerfab/core/errors.h"
#include "kerfab/io/sheet_files.h"

namespace kerfab {

void write_svg_sheets(const RunResult& run, const std::filesystem::path& cut_dir,
                      const SheetStyle& style) {
  const LayoutResult& layout = *run.layout;
  const LayoutOptions& lo = run.options.layout;
  for (int sheet = 0; sheet < layout.sheets; ++sheet) {
    std::ostringstream svg;
    svg.precision(10);
    svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << lo.sheet_width
        << "mm\" height=\"" << lo.sheet_height << "mm\" viewBox=\"0 0 " << lo.sheet_width << " "
        << lo.sheet_height << "\">\n"
        << "<title>kerfab sheet " << sheet + 1 << " of " << layout.sheets << "</title>\n";
    // Sheet coordinates have y up; SVG's go down.
    auto point = [&](const Placement& pl, const Vec2& p) {
      const Vec2 q = pl.apply(p);
      std::ostringstream os;
      os.precision(10);
      os << q.x() << " " << lo.sheet_height - q.y();
      return os.str();
    };
    const std::string line_style =
        "fill=\"none\" stroke-width=\"" + std::to_string(style.stroke) + "\" stroke=\"";
    for (std::size_t part = 0; part < layout.placements.size(); ++part) {
      const Placement& pl = layout.placements[part];
      if (pl.sheet != sheet) continue;
      char id[32];
      std::snprintf(id, sizeof id, "%03zu", part);
      svg << "<g class=\"part\" id=\"part-" << id << "\">\n";
      if (run.engravings.size() > part && !run.engravings[part].empty()) {
        svg << "<path class=\"label\" " << line_style << style.engrave << "\" d=\"";
        for (const Label& label : run.engravings[part])
          for (const auto& s : label_strokes(upright(label, pl.angle)))
            svg << "M " << point(pl, s[0]) << " L " << point(pl, s[1]) << " ";
        svg << "\"/>\n";
        // The texts too, for people and tools reading the file; hidden, so the laser engraves
        // only the strokes above.
        for (const Label& label : run.engravings[part]) {
          const Label l = upright(label, pl.angle);
          const std::string at = point(pl, l.origin);
          svg << "<text class=\"label\" visibility=\"hidden\" font-size=\"" << l.height << "\" x=\""
              << at.substr(0, at.find(' ')) << "\" y=\"" << at.substr(at.find(' ') + 1) << "\">"
              << l.text << "</text>\n";
        }
      }
      if (run.kerf && !run.kerf->patches[part].cuts.empty()) {
        svg << "<path class=\"kerf\" " << line_style << style.cut << "\" d=\"";
        for (const auto& c : run.kerf->patches[part].cuts)
          svg << "M " << point(pl, c.a) << " L " << point(pl, c.b) << " ";
        svg << "\"/>\n";
      }
      const Polygon2& outline = run.joints->parts[part].cut;
      svg << "<path class=\"outline\" " << line_style << style.cut << "\" d=\"";
      for (std::size_t i = 0; i < outline.size(); ++i)
        svg << (i ? "L " : "M ") << point(pl, outline[i]) << " ";
      svg << "Z\"/>\n</g>\n";
    }
    svg << "</svg>\n";
    write_text_file(sheet_file(cut_dir, sheet, "svg"), svg.str());
  }
}

}  // namespace kerfab
