// kerfab_audit DIR [--quiet] [--kerf-width MM] [--min-cut-spacing MM]: the independent sheet
// check of tests/sheet_audit.h on a run's cut/ folder, for looking at any output by hand, with
// the laser the run was made for: its kerf width, cut spacing and shortest cut as DIR/report.json
// states them (options.kerf_width_mm, min_cut_spacing_mm, min_cut_length_mm), else kerfab's
// defaults (0.15 mm kerf, cuts 0.9 mm apart and 2 mm long); the flags win over both. Prints the
// laser it audits for, the counts and every finding.
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "sheet_audit.h"

int main(int argc, char** argv) {
  const char* usage =
      "usage: kerfab_audit OUT_DIR [--quiet] [--kerf-width MM] [--min-cut-spacing MM]\n";
  if (argc < 2) {
    std::cerr << usage;
    return 2;
  }
  kerfab::test::AuditLimits limits;
  // The run's own laser, where its report says.
  std::string source = "kerfab's defaults";
  if (std::ifstream in(std::filesystem::path(argv[1]) / "report.json"); in) {
    const auto report = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (report.is_object() && report.contains("options") && report["options"].is_object()) {
      const auto& o = report["options"];
      const auto take = [&](const char* key, double& value) {
        if (o.contains(key) && o[key].is_number() && o[key].get<double>() >= 0)
          value = o[key].get<double>();
      };
      take("kerf_width_mm", limits.kerf_width);
      take("min_cut_spacing_mm", limits.min_cut_spacing);
      take("min_cut_length_mm", limits.min_cut_length);
      source = "report.json";
    }
  }
  bool quiet = false;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quiet") {
      quiet = true;
    } else if ((arg == "--kerf-width" || arg == "--min-cut-spacing") && i + 1 < argc) {
      char* end = nullptr;
      const double v = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(v >= 0)) {
        std::cerr << usage;
        return 2;
      }
      (arg == "--kerf-width" ? limits.kerf_width : limits.min_cut_spacing) = v;
      source = source == "report.json" ? "report.json and the flags" : "the flags";
    } else {
      std::cerr << usage;
      return 2;
    }
  }
  const auto a = kerfab::test::audit_sheets(std::filesystem::path(argv[1]) / "cut", limits);
  if (!quiet)
    std::cout << "laser (" << source << "): kerf " << limits.kerf_width << " mm, cuts "
              << limits.min_cut_spacing << " mm apart, " << limits.min_cut_length
              << " mm long at least\n";
  if (!quiet)
    for (const auto& f : a.findings) std::cout << f << "\n";
  // Distances measured on no pair (no two cuts in one part; no two parts' boxes within the gap
  // of each other) are said so, not printed as the 1e300 they start from.
  const auto closest = [](double d, const char* none) {
    return d < 1e299 ? std::to_string(d) + " mm" : std::string(none);
  };
  std::cout << "sheets " << a.sheets << ", parts " << a.parts << ", cuts " << a.cuts
            << "; cut pairs closer than the spacing " << a.close_cut_pairs << " (closest "
            << closest(a.closest_cuts, "none: no part has two cuts") << "), short cuts "
            << a.short_cuts << ", small parts " << a.small_parts << ", narrow parts "
            << a.narrow_parts << ", thin tails/slits " << a.thin_features
            << ", engraving off part/over cuts " << a.labels_off_part
            << ", parts closer than the gap " << a.close_part_pairs << " (closest "
            << closest(a.closest_parts, "none measured: no two parts' boxes within the gap")
            << ")\n";
  return a.clean() ? 0 : 1;
}
