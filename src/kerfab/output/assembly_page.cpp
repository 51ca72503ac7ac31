#include "kerfab/output/assembly_page.h"

#include <sstream>

#include "kerfab/output/sheet_files.h"

namespace kerfab {

void write_assembly_page(const RunResult& run, const std::filesystem::path& cut_dir) {
  const auto& neighbours = run.layout->neighbours;
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
    html << "<tr><td>" << p << "</td><td>" << run.layout->sheet_number(static_cast<int>(p))
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
