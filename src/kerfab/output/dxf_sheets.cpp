#include "kerfab/output/dxf_sheets.h"

#include <cstdio>
#include <sstream>

#include "kerfab/output/sheet_files.h"

namespace kerfab {
namespace {

void pair(std::ostream& out, int code, const std::string& value) {
  out << code << "\n" << value << "\n";
}
void pair(std::ostream& out, int code, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6f", value);
  pair(out, code, std::string(buffer));
}

void line(std::ostream& out, const char* layer, const Vec2& a, const Vec2& b) {
  pair(out, 0, "LINE");
  pair(out, 8, layer);
  pair(out, 10, a.x());
  pair(out, 20, a.y());
  pair(out, 30, 0.0);
  pair(out, 11, b.x());
  pair(out, 21, b.y());
  pair(out, 31, 0.0);
}

}  // namespace

void write_dxf_sheets(const RunResult& run, const std::filesystem::path& cut_dir) {
  const LayoutResult& layout = *run.layout;
  for (int sheet = 0; sheet < layout.sheets; ++sheet) {
    std::ostringstream out;
    pair(out, 0, "SECTION");
    pair(out, 2, "HEADER");
    pair(out, 9, "$ACADVER");
    pair(out, 1, "AC1009");
    pair(out, 9, "$INSUNITS");
    pair(out, 70, "4");  // millimetres
    pair(out, 9, "$MEASUREMENT");
    pair(out, 70, "1");  // metric
    pair(out, 9, "$EXTMIN");
    pair(out, 10, 0.0);
    pair(out, 20, 0.0);
    pair(out, 9, "$EXTMAX");
    pair(out, 10, layout.sheet_size(sheet).x());
    pair(out, 20, layout.sheet_size(sheet).y());
    pair(out, 0, "ENDSEC");
    pair(out, 0, "SECTION");
    pair(out, 2, "TABLES");
    pair(out, 0, "TABLE");
    pair(out, 2, "LAYER");
    pair(out, 70, "5");
    for (const auto& [name, colour] :
         {std::pair{"CUT", "1"}, {"KERF", "1"}, {"LABEL", "5"}, {"FOLD_MOUNTAIN", "6"},
          {"FOLD_VALLEY", "3"}}) {
      pair(out, 0, "LAYER");
      pair(out, 2, name);
      pair(out, 70, "0");
      pair(out, 62, colour);  // 1 red (cut), 5 blue (engrave), 6 magenta, 3 green (folds)
      pair(out, 6, "CONTINUOUS");
    }
    pair(out, 0, "ENDTAB");
    pair(out, 0, "ENDSEC");
    pair(out, 0, "SECTION");
    pair(out, 2, "ENTITIES");
    for (const PlacedPart& p : sheet_parts(run, sheet)) {
      // Inside first: engraving, kerf cuts, then the outline.
      for (const auto& s : p.engraving) line(out, "LABEL", s[0], s[1]);
      for (const auto& c : p.kerf) line(out, "KERF", c[0], c[1]);
      for (const PlacedFold& f : p.folds)
        for (std::size_t i = 0; i + 1 < f.points.size(); ++i)
          line(out, f.mountain ? "FOLD_MOUNTAIN" : "FOLD_VALLEY", f.points[i], f.points[i + 1]);
      pair(out, 0, "POLYLINE");
      pair(out, 8, "CUT");
      pair(out, 66, "1");
      pair(out, 70, "1");  // closed
      for (const auto& v : p.outline) {
        pair(out, 0, "VERTEX");
        pair(out, 8, "CUT");
        pair(out, 10, v.x());
        pair(out, 20, v.y());
        pair(out, 30, 0.0);
      }
      pair(out, 0, "SEQEND");
      pair(out, 8, "CUT");
    }
    pair(out, 0, "ENDSEC");
    pair(out, 0, "EOF");
    write_text_file(sheet_file(cut_dir, sheet, "dxf"), out.str());
  }
}

}  // namespace kerfab
