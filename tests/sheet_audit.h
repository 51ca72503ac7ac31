#pragma once
// An independent check of written cut sheets: reads cut/sheet-NNN.svg back (its own parser, not
// kerfab's writer) and measures what a maker would find at the laser: cuts closer than the
// laser can make, cuts too short to cut, parts too small or narrow to handle, thin tails and
// slits in outlines, engraving off its part or across a cut, parts laid out too close together.
#include <filesystem>
#include <string>
#include <vector>

#include "kerfab/core/geometry2d.h"

namespace kerfab::test {

struct AuditLimits {
  double min_cut_spacing = 0.9;  ///< [mm]
  double min_cut_length = 2.0;   ///< [mm]
  double min_part_area = 50;     ///< [mm^2]
  double min_part_width = 3;     ///< [mm]: the outline shrunk by half of it is not empty
  double min_feature = 1.0;      ///< tails and slits narrower than this [mm]
  double label_clearance = 0.2;  ///< engraving keeps this far inside the outline and off cuts [mm]
  double kerf_width = 0.15;      ///< the laser path runs half of it outside the part [mm]
  double min_part_gap = 1.0;     ///< between two parts' laser paths on one sheet, so the strip
                                 ///< of scrap between them does not burn away [mm]
};

struct SheetPart {
  std::string id;  ///< "part-NNN"
  int sheet = 0;
  Polygon2 outline;
  std::vector<std::array<Vec2, 2>> kerf, engraving;
  struct Fold {
    std::vector<Vec2> points;
    std::string kind;  ///< its data-fold attribute: "mountain" or "valley"
    std::string stroke, dashes;
  };
  std::vector<Fold> folds;  ///< <path class="fold"> (paper)
};

struct SheetAudit {
  int sheets = 0, parts = 0, cuts = 0;
  int close_cut_pairs = 0;  ///< pairs of cuts of one part closer than min_cut_spacing
  double closest_cuts = 1e300;
  int short_cuts = 0;       ///< shorter than min_cut_length
  int small_parts = 0;      ///< area below min_part_area
  int narrow_parts = 0;     ///< nothing left after shrinking by min_part_width / 2
  int thin_features = 0;    ///< tails or slits narrower than min_feature
  int labels_off_part = 0;  ///< engraving strokes outside the part's inset or across a cut
  int close_part_pairs = 0;  ///< pairs of parts on one sheet closer than min_part_gap
  double closest_parts = 1e300;  ///< smallest gap between two parts' laser paths [mm]
  std::vector<std::string> findings;  ///< one line per defect, naming part and place
  bool clean() const {
    return close_cut_pairs + short_cuts + small_parts + narrow_parts + thin_features +
               labels_off_part + close_part_pairs ==
           0;
  }
};

/// Every part of every sheet-NNN.svg in \p cut_dir.
std::vector<SheetPart> read_sheet_parts(const std::filesystem::path& cut_dir);

SheetAudit audit_sheets(const std::filesystem::path& cut_dir, const AuditLimits& limits = {});

}  // namespace kerfab::test
