// kerfab_audit DIR [--quiet] [--kerf-width MM] [--min-cut-spacing MM]: the independent sheet
// check of tests/sheet_audit.h on a run's cut/ folder, for looking at any output by hand, with
// the laser the run was made for (its defaults: 0.15 mm kerf, cuts 0.9 mm apart). Prints the
// counts and every finding.
#include <cstdlib>
#include <iostream>
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
    } else {
      std::cerr << usage;
      return 2;
    }
  }
  const auto a = kerfab::test::audit_sheets(std::filesystem::path(argv[1]) / "cut", limits);
  if (!quiet)
    for (const auto& f : a.findings) std::cout << f << "\n";
  std::cout << "sheets " << a.sheets << ", parts " << a.parts << ", cuts " << a.cuts
            << "; cut pairs closer than the spacing " << a.close_cut_pairs << " (closest "
            << a.closest_cuts << " mm), short cuts " << a.short_cuts << ", small parts "
            << a.small_parts << ", narrow parts " << a.narrow_parts << ", thin tails/slits "
            << a.thin_features << ", engraving off part/over cuts " << a.labels_off_part
            << ", parts closer than the gap " << a.close_part_pairs << " (closest "
            << a.closest_parts << " mm)\n";
  return a.clean() ? 0 : 1;
}
