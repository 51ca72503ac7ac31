#include "kerfab/output/sheet_files.h"

#include <cstdio>
#include <fstream>

#include "kerfab/core/errors.h"

namespace kerfab {

std::vector<PlacedPart> sheet_parts(const RunResult& run, int sheet) {
  std::vector<PlacedPart> out;
  const LayoutResult& layout = *run.layout;
  for (std::size_t part = 0; part < layout.placements.size(); ++part) {
    const Placement& pl = layout.placements[part];
    if (pl.sheet != sheet) continue;
    PlacedPart p;
    p.part = static_cast<int>(part);
    if (part < layout.engravings.size())
      for (const Label& label : layout.engravings[part]) {
        const Label l = upright(label, pl.angle);
        for (const auto& s : label_strokes(l))
          p.engraving.push_back({pl.apply(s[0]), pl.apply(s[1])});
        Label placed = l;
        placed.origin = pl.apply(l.origin);
        placed.angle = l.angle + pl.angle;
        p.labels.push_back(placed);
      }
    if (run.kerf)
      for (const auto& c : run.kerf->patches[part].cuts)
        p.kerf.push_back({pl.apply(c.a), pl.apply(c.b)});
    for (const FoldLine& f : run.joints->parts[part].folds) {
      PlacedFold placed;
      placed.mountain = f.mountain();
      for (const Vec2& v : f.points) placed.points.push_back(pl.apply(v));
      p.folds.push_back(std::move(placed));
    }
    for (const auto& v : run.joints->parts[part].cut) p.outline.push_back(pl.apply(v));
    out.push_back(std::move(p));
  }
  return out;
}

std::filesystem::path sheet_file(const std::filesystem::path& cut_dir, int sheet,
                                 const std::string& extension) {
  std::error_code ec;
  std::filesystem::create_directories(cut_dir, ec);
  if (ec) throw IoError("cannot create " + cut_dir.string() + ": " + ec.message());
  char name[32];
  std::snprintf(name, sizeof name, "sheet-%03d.", sheet + 1);
  return cut_dir / (name + extension);
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  if (!file) throw IoError("cannot write " + path.string());
}

}  // namespace kerfab
