#include "kerfab/output/svg_sheets.h"

#include <cstdio>
#include <sstream>

#include "kerfab/output/sheet_files.h"

namespace kerfab {

void write_svg_sheets(const RunResult& run, const SheetStyle& style,
                      const std::filesystem::path& cut_dir) {
  const LayoutResult& layout = *run.layout;
  for (int sheet = 0; sheet < layout.sheets; ++sheet) {
    const double width = layout.sheet_size(sheet).x(), height = layout.sheet_size(sheet).y();
    std::ostringstream svg;
    svg.precision(10);
    svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "mm\" height=\""
        << height << "mm\" viewBox=\"0 0 " << width << " " << height << "\">\n"
        << "<title>kerfab sheet " << sheet + 1 << " of " << layout.sheets << "</title>\n";
    // Sheet coordinates have y up; SVG's go down.
    auto point = [&](const Vec2& q) {
      std::ostringstream os;
      os.precision(10);
      os << q.x() << " " << height - q.y();
      return os.str();
    };
    const std::string line_style =
        "fill=\"none\" stroke-width=\"" + std::to_string(style.stroke) + "\" stroke=\"";
    for (const PlacedPart& p : sheet_parts(run, sheet)) {
      char id[32];
      std::snprintf(id, sizeof id, "%03d", p.part);
      svg << "<g class=\"part\" id=\"part-" << id << "\">\n";
      if (!p.engraving.empty()) {
        svg << "<path class=\"label\" " << line_style << style.engrave << "\" d=\"";
        for (const auto& s : p.engraving) svg << "M " << point(s[0]) << " L " << point(s[1]) << " ";
        svg << "\"/>\n";
        // The texts too, for people and tools reading the file; hidden, so the laser engraves
        // only the strokes above.
        for (const Label& l : p.labels)
          svg << "<text class=\"label\" visibility=\"hidden\" font-size=\"" << l.height << "\" x=\""
              << l.origin.x() << "\" y=\"" << height - l.origin.y() << "\">" << l.text
              << "</text>\n";
      }
      if (!p.kerf.empty()) {
        svg << "<path class=\"kerf\" " << line_style << style.cut << "\" d=\"";
        for (const auto& c : p.kerf) svg << "M " << point(c[0]) << " L " << point(c[1]) << " ";
        svg << "\"/>\n";
      }
      for (const PlacedFold& f : p.folds) {
        svg << "<path class=\"fold\" data-fold=\"" << (f.mountain ? "mountain" : "valley")
            << "\" " << line_style << (f.mountain ? style.mountain : style.valley)
            << "\" stroke-dasharray=\"";
        if (f.mountain)
          for (double d : kMountainDash) svg << d << " ";
        else
          for (double d : kValleyDash) svg << d << " ";
        svg << "\" d=\"";
        for (std::size_t i = 0; i < f.points.size(); ++i)
          svg << (i ? "L " : "M ") << point(f.points[i]) << " ";
        svg << "\"/>\n";
      }
      svg << "<path class=\"outline\" " << line_style << style.cut << "\" d=\"";
      for (std::size_t i = 0; i < p.outline.size(); ++i)
        svg << (i ? "L " : "M ") << point(p.outline[i]) << " ";
      svg << "Z\"/>\n</g>\n";
    }
    svg << "</svg>\n";
    write_text_file(sheet_file(cut_dir, sheet, "svg"), svg.str());
  }
}

}  // namespace kerfab
