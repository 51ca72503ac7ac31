#include "kerfab/io/assembly_page.h"

#include <sstream>

#include "kerfab/io/sheet_files.h"

namespace kerfab {

std::vector<std::map<int, double>> part_neighbours(const RunResult& run) {
  std::vector<std::map<int, double>> out(run.strips ? run.strips->patches.size() : 0);
  if (!run.joints) return out;
  for (const BorderJoint& b : run.joints->borders) {
    out[b.patches[0]][b.patches[1]] += b.length;
    if (b.patches[1] != b.patches[0]) out[b.patches[1]][b.patches[0]] += b.length;
  }
  return out;
}

nlohmann::json make_assembly_json(const RunResult& run) {
  const auto neighbours = part_neighbours(run);
  nlohmann::json parts = nlohmann::json::array();
  for (std::size_t p = 0; p < neighbours.size(); ++p) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& [q, length] : neighbours[p])
      list.push_back({{"part", q}, {"length_mm", length}});
    const int sheet =
        run.layout && p < run.layout->placements.size() ? run.layout->placements[p].sheet + 1 : 0;
    parts.push_back({{"part", p}, {"sheet", sheet}, {"neighbours", list}});
  }
  return parts;
}

void write_assembly_page(const RunResult& run, const std::filesystem::path& cut_dir) {
  const auto neighbours = part_neighbours(run);
  std::ostringstream html;
  html.precision(4);
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>kerfab assembly</title>"
       << "<style>body{font-family:sans-serif}td,th{padding:2px 10px;text-align:left}"
       << "tr:nth-child(even){background:#eee}</style></head><body>\n"
       << "<h1>Assembly: " << neighbours.size() << " parts</h1>\n"
       << "<p>Each part carries its number engraved. Glue it to the parts listed, along the "
          "borders whose box joints fit together; lengths are the shared border in mm. A part "
          "listed as its own neighbour closes into a ring.</p>\n"
       << "<table><tr><th>part</th><th>sheet</th><th>joins</th></tr>\n";
  for (std::size_t p = 0; p < neighbours.size(); ++p) {
    html << "<tr><td>" << p << "</td><td>"
         << (run.layout && p < run.layout->placements.size() ? run.layout->placements[p].sheet + 1
                                                             : 0)
         << "</td><td>";
    bool first = true;
    for (const auto& [q, length] : neighbours[p]) {
      html << (first ? "" : ", ") << q << " (" << length << " mm)";
      first = false;
    }
    html << "</td></tr>\n";
  }
  html << "</table>\n</body></html>\n";
  std::error_code ec;
  std::filesystem::create_directories(cut_dir, ec);
  write_text_file(cut_dir / "assembly.html", html.str());
}

}  // namespace kerfab
