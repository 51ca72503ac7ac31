#pragma once
/// \file Engraved labels: single-stroke digits (no font needed at the laser), placed on each part
/// where they fit entirely inside its outline (teeth and slots as cut) and clear of its kerf
/// cuts and of each other.
#include <optional>
#include <string>
#include <vector>

#include "kerfab/adapters/polygon_ops.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/joints/joints.h"
#include "kerfab/kerf/kerf.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

struct Label {
  std::string text;
  Vec2 origin{0, 0};  ///< lower left of the first glyph, in the part's flattened frame [mm]
  double angle = 0;   ///< baseline direction [rad]
  double height = 0;  ///< glyph height [mm]
};

/// Stroke segments ({a, b} pairs) drawing \p label in the part's frame: seven-segment digits
/// (and '-') over an underline. Other characters are skipped.
std::vector<std::array<Vec2, 2>> label_strokes(const Label& label);

/// The same label turned half a turn about its centre if, once the part is turned by
/// \p placement_angle on the sheet, it would read upside down (7-segment "52" upside down is
/// "25").
Label upright(const Label& label, double placement_angle);

/// The part's number, as large as fits (at most \p max_height mm, at least 1 mm) inside
/// \p outline (the part as cut, in its flattened frame) by 0.4 mm and at least 0.4 mm from every
/// kerf cut; along the strip or across it between two cuts, nearest its middle (a facet: along
/// its longest edge, nearest its centre). Empty when nothing fits.
std::optional<Label> part_label(const Strips& strips, const Flattening& flat,
                                const KerfResult& kerf, const Polygon2& outline, int patch,
                                double max_height = 5.0);

/// For every part this one joins, "-N" (N: the neighbour's number) engraved next to the shared
/// border, along it and just inside, as near its middle as there is room (within 40 mm), 3 mm
/// down to 1 mm tall, with the clearances of part_label and off \p part_label; borders with no
/// room get no label.
std::vector<Label> border_labels(const Strips& strips, const Flattening& flat,
                                 const KerfResult& kerf, const Joints& joints,
                                 const Polygon2& outline, int patch,
                                 const std::optional<Label>& part_label);

}  // namespace kerfab
