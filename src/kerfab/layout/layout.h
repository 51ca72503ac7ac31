#pragma once
/// \file Cut-sheet layout: every part (its laser path, with its kerf cuts) is turned and placed
/// on as few sheets as possible, testing the real outlines for overlap (Clipper), not only their
/// bounding boxes.
#include <string>
#include <vector>

#include "kerfab/adapters/polygon_ops.h"

namespace kerfab {

struct LayoutOptions {
  double sheet_width = 600;   ///< [mm], > 0
  double sheet_height = 450;  ///< [mm], > 0
  double margin = 10;         ///< kept free along the sheet's edges [mm], >= 0
  double spacing = 3;         ///< between parts [mm], >= 0
  double step = 1.0;          ///< cell of the occupancy grid parts are placed on [mm], > 0
};

/// How cut sheets draw their lines.
struct SheetStyle {
  std::string cut = "#ff0000";      ///< colour of cut lines (outlines, kerf cuts), #rrggbb
  std::string engrave = "#0000ff";  ///< colour of engraved labels, #rrggbb
  double stroke = 0.01;             ///< line width in SVG and PDF [mm], > 0 (hairline)
};

/// Where a part goes: p_sheet = R(angle) * p_part + offset.
struct Placement {
  int sheet = -1;
  double angle = 0;  ///< [rad]
  Eigen::Vector2d offset{0, 0};
  Eigen::Vector2d apply(const Eigen::Vector2d& p) const;
};

struct LayoutResult {
  std::vector<Placement> placements;  ///< per part; sheet -1: does not fit any sheet
  int sheets = 0;
  double utilization = 0;  ///< parts' area / sheets' area [-]
  std::vector<int> unplaced;
};

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
/// an outline touches counts as taken, so concave parts interlock but never overlap). \throw
/// InvalidInput options out of range.
LayoutResult nest_parts(const std::vector<Polygon2>& outlines, const LayoutOptions& options);

}  // namespace kerfab
