// kerfab_audit DIR: the independent sheet check of tests/sheet_audit.h on a run's cut/ folder,
// for looking at any output by hand. Prints the counts and every finding.
#include <iostream>

#include "sheet_audit.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: kerfab_audit OUT_DIR [--quiet]\n";
    return 2;
  }
  const auto a = kerfab::test::audit_sheets(std::filesystem::path(argv[1]) / "cut");
  const bool quiet = argc > 2 && std::string(argv[2]) == "--quiet";
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
