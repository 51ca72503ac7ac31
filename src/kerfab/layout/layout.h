#pragma once
/// \file Cut-sheet layout: every part (its laser path, with its kerf cuts) is turned and placed
/// on as few sheets as possible, testing the real outlines for overlap (Clipper), not only their
/// bounding boxes.
#include <map>
#include <optional>
#include <vector>

#include "kerfab/adapters/polygon_ops.h"
#include "kerfab/layout/labels.h"

namespace kerfab {

struct LayoutOptions {
  double sheet_width = 600;   ///< the stock sheet, as many as needed [mm], > 0
  double sheet_height = 450;  ///< [mm], > 0
  /// Offcuts: sheets (width, height) [mm] filled before the stock sheets, one each, in this
  /// order; one that no part fits is not used.
  std::vector<Vec2> offcuts;
  /// The size of sheet \p k as nest_parts fills them: the offcuts, then the stock sheet [mm].
  Vec2 size_of(int k) const {
    return k >= 0 && k < static_cast<int>(offcuts.size()) ? offcuts[k]
                                                          : Vec2(sheet_width, sheet_height);
  }
  double margin = 10;  ///< kept free along the sheet's edges [mm], >= 0
  double spacing = 3;  ///< between parts [mm], >= 0
  double step = 1.0;   ///< cell of the occupancy grid parts are placed on [mm], > 0
};

/// Where a part goes: p_sheet = R(angle) * p_part + offset.
struct Placement {
  int sheet = -1;
  double angle = 0;  ///< [rad]
  Vec2 offset{0, 0};
  Vec2 apply(const Vec2& p) const;
};

struct LayoutResult {
  std::vector<Placement> placements;  ///< per part; sheet -1: does not fit any sheet
  int sheets = 0;
  std::vector<Vec2> sheet_sizes;  ///< per sheet used: its width and height [mm]
  /// The size of sheet \p k (0-based) [mm].
  Vec2 sheet_size(int k) const { return sheet_sizes.at(k); }
  double utilization = 0;                 ///< parts' area / sheets' area [-]
  std::vector<double> sheet_utilization;  ///< per sheet: its parts' area / its area [-]
  /// No nesting can use fewer sheets than this: the placed parts' area over one sheet's usable
  /// area (inside the margins), rounded up.
  int sheets_lower_bound = 0;
  /// The same with the spacing counted: parts grown by half the spacing do not overlap and lie
  /// within the usable area grown by half the spacing, so their area over that one's is a
  /// lower bound as well, and a tighter one.
  int sheets_lower_bound_spaced = 0;
  /// The same before rounding up: how many sheets the grown parts fill [-].
  double spaced_fill = 0;
  std::vector<int> unplaced;  ///< parts on no sheet: larger than any, or nothing left (below)
  std::vector<int> empty;     ///< of those, parts with no outline left to cut (their joints'
                              ///< slots and mitres took all of them)
  /// How many parts are on no sheet because they are larger than any.
  std::size_t too_large() const { return unplaced.size() - empty.size(); }
  // Filled by lay_out_parts (not by nest_parts):
  std::vector<std::optional<Label>> labels;       ///< per part: its number, if it fits
  std::vector<std::vector<Label>> engravings;     ///< per part: its number and border labels
  std::vector<std::map<int, double>> neighbours;  ///< per part: neighbour -> shared border [mm]
                                                  ///< (a part may join itself after a loop cut)
  int border_labels_placed = 0;                   ///< "-N" labels engraved
  int border_labels_wanted = 0;                   ///< borders with another part
  /// The 1-based sheet \p part is on, as the files and the report number them; 0: on none.
  int sheet_number(int part) const {
    return part >= 0 && part < static_cast<int>(placements.size()) ? placements[part].sheet + 1 : 0;
  }
};

/// The fullest sheets the nesting reaches: the parts grown by half the spacing cover about this
/// much of a sheet's usable area, grown alike, on every sheet but the last (0.77-0.80 on Spot at
/// 500 mm, Amo and the quad sphere on small sheets; stanford-bunny's 365 parts 0.76 on one
/// sheet) [-]. Where LayoutResult::spaced_fill is more than this times one sheet fewer, no
/// nesting of these parts is likely to save a sheet. (On the 0.5 mm grid by the far corner the
/// quad sphere's 164 parts reached 0.835 on each of 3 sheets of 400 x 300; at 0.85 here, the
/// benchmark's quad sphere on 300 x 300 and Amo on 300 x 250 sheets tried that grid and
/// split_to_fit, 1.3 and 4 s more, and saved no sheet.)
constexpr double kFullestSheet = 0.8;

/// Nesting is cheap (about 2 s on 2 cores) where parts x sheets is at most this: only then are
/// more orders and rules tried (Spot at 500 mm with 4 Catmull-Clark steps, 578 parts on 10
/// sheets, took 13.6 s for one pass and 57 s for all) [-].
constexpr double kCheapNest = 2000;

/// True when parts grown by half the spacing that fill \p spaced_fill sheets
/// (LayoutResult::spaced_fill) would have to fill the sheets but one of \p sheets fuller than
/// kFullestSheet: no nesting here is likely to save that sheet.
inline bool too_full_for_one_fewer(double spaced_fill, int sheets) {
  return spaced_fill > kFullestSheet * (sheets - 1);
}

/// Smallest-area enclosing rectangle of a polygon's convex hull: its angle [rad] (turning the
/// polygon by -angle makes the rectangle axis-aligned) and size [mm].
struct MinRect {
  double angle = 0, width = 0, height = 0;
};
MinRect min_area_rect(const Polygon2& polygon);

/// True when a part with this outline fits the sheet's usable area in some orientation.
bool fits_sheet(const Polygon2& outline, const LayoutOptions& options);

/// Places the parts (largest first, bottom-left, trying the minimum-rectangle orientation and
/// its quarter turns) on an occupancy grid of the outlines grown by half the spacing (every cell
/// an outline touches counts as taken, so concave parts interlock but never overlap), and
/// computes the two lower bounds on the sheets. When that needs more sheets than the spaced
/// bound, it also tries the parts with the largest minimum rectangle first and the longest
/// first, each with a second placing rule (the free position whose far corner is nearest the
/// sheet's origin), then the parts of the best pass's last sheet first; every pass then tries
/// to move its last sheet's parts into the other sheets' gaps, turned in 10 degree steps; where
/// the grown parts could still fill a sheet fewer, largest first once more on a grid of half
/// the step. It keeps the pass with the fewest sheets (then the emptiest last sheet).
/// \throw InvalidInput
/// options out of range (check_sheets).
LayoutResult nest_parts(const std::vector<Polygon2>& outlines, const LayoutOptions& options);

/// Sheet sizes, margin and spacing a layout can use: every sheet larger than twice the margin
/// both ways, and wider inside its margins than the spacing (each part takes half of it on
/// every side). The pipeline calls it before any stage runs (a 1 x 1 mm sheet was refused only
/// after every stage had run). \throw InvalidInput naming the sheet that has no room.
void check_sheets(const LayoutOptions& options);

/// Per part: neighbour part -> total shared border length [mm] (3D length of the border pieces).
std::vector<std::map<int, double>> part_neighbours(const Joints& joints, int parts);

/// The layout stage: the parts' laser paths nested on sheets (nest_parts), each part's engraved
/// number and border labels, and who joins whom. \throw InvalidInput options out of range.
LayoutResult lay_out_parts(const Strips& strips, const Flattening& flat, const Joints& joints,
                           const KerfResult& kerf, const LayoutOptions& options);

}  // namespace kerfab
