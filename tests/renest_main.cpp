// kerfab_renest OUT_DIR [WxH] [spacing]: reads a run's written sheets back (tests/sheet_audit.h)
// and nests the same part outlines again with the current nester, printing sheets against the
// area lower bound, utilisation and time. KERFAB_RENEST_STEP and KERFAB_RENEST_MARGIN [mm] set
// the grid step and the margin. For measuring the nester by hand on real parts.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "kerfab/layout/layout.h"
#include "sheet_audit.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: kerfab_renest OUT_DIR [WxH] [spacing_mm]\n";
    return 2;
  }
  kerfab::LayoutOptions o;
  if (argc > 2 && std::sscanf(argv[2], "%lfx%lf", &o.sheet_width, &o.sheet_height) != 2) {
    std::cerr << "kerfab_renest: sheet must be WxH in mm\n";
    return 2;
  }
  if (argc > 3) o.spacing = std::atof(argv[3]);
  if (const char* v = std::getenv("KERFAB_RENEST_STEP")) o.step = std::atof(v);
  if (const char* v = std::getenv("KERFAB_RENEST_MARGIN")) o.margin = std::atof(v);
  std::vector<kerfab::Polygon2> outlines;
  for (auto& part : kerfab::test::read_sheet_parts(std::filesystem::path(argv[1]) / "cut"))
    outlines.push_back(std::move(part.outline));
  const auto start = std::chrono::steady_clock::now();
  const kerfab::LayoutResult r = kerfab::nest_parts(outlines, o);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<double> on_sheet(std::max(1, r.sheets), 0.0);
  for (std::size_t i = 0; i < outlines.size(); ++i)
    if (r.placements[i].sheet >= 0)
      on_sheet[r.placements[i].sheet] += std::abs(kerfab::polygon_area(outlines[i]));
  const double usable = (o.sheet_width - 2 * o.margin) * (o.sheet_height - 2 * o.margin);
  // How full the sheets of the spaced bound would have to be.
  std::cout << "grown parts fill " << 100 * r.spaced_fill << "% of one sheet; ";
  std::cout << "last sheet " << 100 * on_sheet.back() / usable << "% full; ";
  std::cout << outlines.size() << " parts: " << r.sheets << " sheets (area lower bound "
            << r.sheets_lower_bound << ", with the spacing " << r.sheets_lower_bound_spaced << "), utilisation " << r.utilization << ", unplaced "
            << r.unplaced.size() << ", " << s << " s\n";
  // KERFAB_RENEST_SVG=prefix: one plain SVG per sheet with the placed outlines, to look at.
  if (const char* prefix = std::getenv("KERFAB_RENEST_SVG"))
    for (int sheet = 0; sheet < r.sheets; ++sheet) {
      std::ofstream svg(std::string(prefix) + std::to_string(sheet + 1) + ".svg");
      svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << o.sheet_width
          << "mm\" height=\"" << o.sheet_height << "mm\" viewBox=\"0 0 " << o.sheet_width << " "
          << o.sheet_height << "\"><rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
      for (std::size_t i = 0; i < outlines.size(); ++i) {
        if (r.placements[i].sheet != sheet) continue;
        svg << "<path fill=\"#fdd\" stroke=\"red\" stroke-width=\"0.5\" d=\"";
        for (std::size_t k = 0; k < outlines[i].size(); ++k) {
          const auto p = r.placements[i].apply(outlines[i][k]);
          svg << (k ? " L " : "M ") << p.x() << " " << p.y();
        }
        svg << " Z\"/>\n";
      }
      svg << "</svg>\n";
    }
  return 0;
}
