#include "kerfab/layout/layout.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "kerfab/core/errors.h"
#include "kerfab/core/parallel.h"

namespace kerfab {
namespace {

struct Box {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  void add(const Vec2& p) {
    x0 = std::min(x0, p.x()), y0 = std::min(y0, p.y());
    x1 = std::max(x1, p.x()), y1 = std::max(y1, p.y());
  }
  bool overlaps(const Box& b) const {
    return !(b.x0 >= x1 || x0 >= b.x1 || b.y0 >= y1 || y0 >= b.y1);
  }
};

Box box_of(const Polygon2& p) {
  Box b;
  for (const auto& v : p) b.add(v);
  return b;
}

Polygon2 transformed(const Polygon2& p, double angle, const Vec2& offset) {
  const Eigen::Rotation2Dd r(angle);
  Polygon2 out;
  out.reserve(p.size());
  for (const auto& v : p) out.push_back(r * v + offset);
  return out;
}

Polygon2 convex_hull(Polygon2 pts) {
  std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  Polygon2 hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

}  // namespace

Vec2 Placement::apply(const Vec2& p) const { return Eigen::Rotation2Dd(angle) * p + offset; }

MinRect min_area_rect(const Polygon2& polygon) {
  const Polygon2 hull = convex_hull(polygon);
  MinRect best{0, 0, 0};
  double best_area = 1e300;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
    if (e.norm() <= 0) continue;
    const double angle = std::atan2(e.y(), e.x());
    const Box b = box_of(transformed(hull, -angle, Vec2(0, 0)));
    const double area = (b.x1 - b.x0) * (b.y1 - b.y0);
    if (area < best_area) best_area = area, best = {angle, b.x1 - b.x0, b.y1 - b.y0};
  }
  return best;
}

bool fits_sheet(const Polygon2& outline, const LayoutOptions& o) {
  const MinRect r = min_area_rect(outline);
  for (int k = 0; k <= static_cast<int>(o.offcuts.size()); ++k) {  // the offcuts, the stock
    const Vec2 size = o.size_of(k);
    const double w = size.x() - 2 * o.margin, h = size.y() - 2 * o.margin;
    if ((r.width <= w && r.height <= h) || (r.height <= w && r.width <= h)) return true;
  }
  return false;
}

namespace {

/// A part turned to one angle, rasterised on the layout grid: per grid row, the covered columns
/// [from, to) relative to the raster's corner. Conservative: every cell the (grown) outline
/// touches is covered.
struct Raster {
  double angle = 0;
  Vec2 corner{0, 0};  ///< where the raster's cell (0, 0) starts, in the turned part's frame
  int width = 0, height = 0;
  std::vector<std::vector<std::array<int, 2>>> rows;
  int cells = 0;            ///< covered cells in all
  std::vector<int> widest;  ///< per row, its longest span [cells]
};

Raster rasterise(const Polygon2& grown, double angle, double cell) {
  Raster r;
  r.angle = angle;
  const Polygon2 p = transformed(grown, angle, Vec2(0, 0));
  const Box b = box_of(p);
  r.corner = Vec2(b.x0, b.y0);
  r.width = static_cast<int>(std::ceil((b.x1 - b.x0) / cell)) + 1;
  r.height = static_cast<int>(std::ceil((b.y1 - b.y0) / cell)) + 1;
  r.rows.resize(r.height);
  // Each row of cells [y, y + cell): the outline's extent over that band, from its edges'
  // crossings of the band's two lines and its middle line, and the x extent within the band of
  // every edge passing through it. Each edge visits only the rows its y range reaches (two more
  // either side, for rounding), not every row: the same spans as testing every edge against
  // every row, in a fraction of the time (rasterising was half the nesting time of
  // sphere_ico's 40 rings, each of thousands of vertices, turned in 10 degree steps).
  const int rows = r.height;
  std::vector<double> band_lo(rows), band_hi(rows);
  for (int j = 0; j < rows; ++j) band_lo[j] = b.y0 + j * cell, band_hi[j] = band_lo[j] + cell;
  std::vector<std::array<std::vector<double>, 3>> crossings(rows);  // per row, per line
  std::vector<std::vector<std::array<double, 2>>> passing(rows);    // edges' extents per row
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 &u = p[i], &v = p[(i + 1) % p.size()];
    const double y_min = std::min(u.y(), v.y()), y_max = std::max(u.y(), v.y());
    const int j0 = std::max(0, static_cast<int>(std::floor((y_min - b.y0) / cell)) - 2);
    const int j1 = std::min(rows - 1, static_cast<int>(std::floor((y_max - b.y0) / cell)) + 2);
    const bool level = std::abs(v.y() - u.y()) < 1e-12;
    auto x_at = [&](double y) {
      return level ? u.x() : u.x() + (y - u.y()) / (v.y() - u.y()) * (v.x() - u.x());
    };
    for (int j = j0; j <= j1; ++j) {
      const double ya = band_lo[j], yb = band_hi[j];
      const double lines[3] = {ya, yb, 0.5 * (ya + yb)};
      for (int k = 0; k < 3; ++k) {
        const double y = lines[k];
        if ((u.y() <= y) != (v.y() <= y))
          crossings[j][k].push_back(u.x() + (y - u.y()) / (v.y() - u.y()) * (v.x() - u.x()));
      }
      const double lo = std::max(ya, y_min), hi = std::min(yb, y_max);
      if (lo > hi) continue;
      const double x0 = x_at(lo), x1 = x_at(hi);
      passing[j].push_back({std::min({x0, x1, level ? std::min(u.x(), v.x()) : x0}),
                            std::max({x0, x1, level ? std::max(u.x(), v.x()) : x1})});
    }
  }
  for (int j = 0; j < rows; ++j) {
    std::vector<std::array<double, 2>> spans;
    for (std::vector<double>& cross : crossings[j]) {
      std::sort(cross.begin(), cross.end());
      for (std::size_t k = 0; k + 1 < cross.size(); k += 2)
        spans.push_back({cross[k], cross[k + 1]});
    }
    spans.insert(spans.end(), passing[j].begin(), passing[j].end());
    // Rounding may put an end a hair outside the box: cells stay within [0, width] (a span
    // from cell -1 read before the sheet grid's rows; found by AddressSanitizer).
    std::vector<std::array<int, 2>> cells;
    for (const auto& sp : spans)
      cells.push_back(
          {std::clamp(static_cast<int>(std::floor((sp[0] - b.x0) / cell)), 0, r.width),
           std::clamp(static_cast<int>(std::floor((sp[1] - b.x0) / cell)) + 1, 0, r.width)});
    std::sort(cells.begin(), cells.end());
    for (const auto& c : cells) {
      if (!r.rows[j].empty() && c[0] <= r.rows[j].back()[1])
        r.rows[j].back()[1] = std::max(r.rows[j].back()[1], c[1]);
      else
        r.rows[j].push_back(c);
    }
  }
  r.widest.assign(r.height, 0);
  for (int j = 0; j < r.height; ++j)
    for (const auto& span : r.rows[j]) {
      r.cells += span[1] - span[0];
      r.widest[j] = std::max(r.widest[j], span[1] - span[0]);
    }
  return r;
}

/// Occupied cells of one sheet, with per row and column the free run starting there and the
/// first free cell at or after it, for fast tests and jumps; and the free cells in all and per
/// row the longest free run, which rule out sheets and rows where a raster cannot fit at all.
struct SheetGrid {
  int width = 0, height = 0;
  std::vector<std::vector<char>> cells;
  /// Per row, for columns 0..width: free cells from there up to the next occupied one (0 on an
  /// occupied cell and at width), and the first free column from there (width if none).
  std::vector<std::vector<int>> free_run, next_free;
  std::vector<int> occupied;  ///< per row, its occupied cells
  int free_cells = 0;
  std::vector<int> longest_free;
  Vec2 size;  ///< the sheet's width and height [mm]
  /// The grid of cells of \p cell [mm] on a sheet of \p sheet [mm].
  SheetGrid(const Vec2& sheet, double cell)
      : SheetGrid(static_cast<int>(std::floor(sheet.x() / cell)),
                  static_cast<int>(std::floor(sheet.y() / cell))) {
    size = sheet;
  }
  SheetGrid(int w, int h)
      : width(w),
        height(h),
        cells(h, std::vector<char>(w, 0)),
        free_run(h, std::vector<int>(w + 1, 0)),
        next_free(h, std::vector<int>(w + 1, w)),
        occupied(h, 0),
        free_cells(w * h),
        longest_free(h, w) {
    for (int y = 0; y < h; ++y) refresh(y);
  }
  void refresh(int y) {
    free_cells += occupied[y];
    const std::vector<char>& row = cells[y];
    std::vector<int>&run = free_run[y], &next = next_free[y];
    int longest = 0, taken = 0;
    run[width] = 0, next[width] = width;
    for (int x = width - 1; x >= 0; --x) {
      run[x] = row[x] ? 0 : run[x + 1] + 1;
      next[x] = row[x] ? next[x + 1] : x;
      longest = std::max(longest, run[x]);
      taken += row[x] ? 1 : 0;
    }
    occupied[y] = taken;
    free_cells -= taken;
    longest_free[y] = longest;
  }
  /// False where some row of \p r at rows y.. is wider than the longest free run there: no x
  /// can take it.
  bool rows_may_hold(const Raster& r, int y) const {
    for (int j = 0; j < r.height; ++j)
      if (r.widest[j] > longest_free[y + j]) return false;
    return true;
  }
  /// Smallest x' >= x where the raster at (x', y) is free; -1 if none up to x_max.
  /// A row's span that meets an occupied cell moves x to the next column where that span lies
  /// on free cells: every x before is ruled out by that span alone, so the x returned is the
  /// smallest free one whichever clash is found first. \p hint: the raster's row that clashed
  /// last, tested first (and updated): a part sliding along x mostly meets the same neighbour
  /// again.
  int first_free(const Raster& r, int x, int y, int x_max, int& hint) const {
    if (hint < 0 || hint >= r.height) hint = 0;
    while (x <= x_max) {
      int jump = -1;
      // Rows outward from the hint, alternately above and below it, then the rest on the side
      // that has rows left.
      const int h = hint, near = std::min(h, r.height - 1 - h);
      for (int k = 0; k < r.height && jump < 0; ++k) {
        const int j = k <= 2 * near ? (k % 2 ? h + (k + 1) / 2 : h - k / 2)
                                    : (h < r.height - 1 - h ? k : r.height - 1 - k);
        const int* run = free_run[y + j].data();
        const int* next = next_free[y + j].data();
        for (const auto& span : r.rows[j]) {
          const int a = x + span[0], len = std::min(x + span[1], width) - a;
          if (len <= 0 || run[a] >= len) continue;
          // The first start from a with the span's cells free after it.
          int p = a;
          while (p < width && run[p] < len) p = next[p + run[p]];
          jump = p - span[0];
          hint = j;
          break;
        }
      }
      if (jump < 0) return x;
      x = std::max(x + 1, jump);
    }
    return -1;
  }
  void mark(const Raster& r, int x, int y) {
    for (int j = 0; j < r.height; ++j) {
      for (const auto& span : r.rows[j])
        for (int c = std::max(0, x + span[0]); c < std::min(width, x + span[1]); ++c)
          cells[y + j][c] = 1;
      refresh(y + j);
    }
  }
};

}  // namespace

namespace {

/// A part turned to several angles: per angle its raster (grown by half the spacing) and the
/// box of the turned part itself (not grown), for the margins.
struct Turned {
  std::vector<Raster> rasters;
  std::vector<Box> boxes;
};

/// A part ready for placing: its rasters and turned boxes at the minimum-rectangle angle and
/// its quarter turns.
struct Prepared {
  bool fits = false;
  double area = 0, grown_area = 0, rect_area = 0, length = 0;
  double rect_angle = 0;       ///< the minimum rectangle's angle [rad]
  Polygon2 outline, inflated;  ///< as cut, and grown by half the spacing
  Turned quarters;
};

/// \p part at \p turns equal turns of a full circle from its minimum rectangle's angle.
Turned turned(const Prepared& part, int turns, double cell) {
  Turned t;
  for (int k = 0; k < turns; ++k) {
    const double angle = -part.rect_angle + k * 2 * M_PI / turns;
    t.rasters.push_back(rasterise(part.inflated, angle, cell));
    t.boxes.push_back(box_of(transformed(part.outline, angle, Vec2(0, 0))));
  }
  return t;
}

/// Which free position a part takes on a sheet: the lowest, then leftmost (bottom-left), or
/// the one whose far corner (top plus half the right edge) is nearest the sheet's origin,
/// which packs curved strips closer (the quad sphere's sheets from 72-78 % of the grown parts'
/// area to 80-83 %).
/// kNarrowest: bottom-left, and of the turns that reach as low and as far left, the one whose
/// right edge ends first: a rectangle stands on its short side and leaves the width beside it
/// for the next (a 700 mm box on 600 x 450 mm sheets, its faces cut in plates of 350 x 262 mm:
/// bottom-left laid each on its long side, one to a sheet with a strip beside it: 22 sheets;
/// standing, two side by side: 16).
enum class Rule { kBottomLeft, kCorner, kNarrowest };

/// A part's best position on one sheet over the turns given: which of them, and where.
struct Spot {
  int raster = -1, x = 0, y = 0;
};

Spot find_spot(const SheetGrid& grid, const Turned& turns, Rule rule, const LayoutOptions& o) {
  const std::vector<Raster>& rasters = turns.rasters;
  const std::vector<Box>& boxes = turns.boxes;
  const double cell = o.step;
  Spot best;
  double best_score = std::numeric_limits<double>::infinity();
  for (std::size_t q = 0; q < rasters.size(); ++q) {
    const Raster& r = rasters[q];
    if (r.cells > grid.free_cells) continue;
    // Raster cell (0,0) at grid cell (x, y): the part's own box then starts at
    // (x * cell + (box.x0 - corner.x)), which must be >= margin (same for the far side).
    const double dx0 = boxes[q].x0 - r.corner.x(), dx1 = boxes[q].x1 - r.corner.x();
    const double dy0 = boxes[q].y0 - r.corner.y(), dy1 = boxes[q].y1 - r.corner.y();
    const int x_min = std::max(0, static_cast<int>(std::ceil((o.margin - dx0) / cell)));
    const int x_max =
        std::min(grid.width - r.width,
                 static_cast<int>(std::floor((grid.size.x() - o.margin - dx1) / cell)));
    const int y_min = std::max(0, static_cast<int>(std::ceil((o.margin - dy0) / cell)));
    const int y_max =
        std::min(grid.height - r.height,
                 static_cast<int>(std::floor((grid.size.y() - o.margin - dy1) / cell)));
    int hint = 0;
    for (int y = y_min; y <= y_max; ++y) {
      // Both scores grow with y: once the least a row can score is over the best, no lower
      // row can win any more.
      const double least = rule != Rule::kCorner ? y : (y + r.height) + 0.5 * (x_min + r.width);
      if (best.raster >= 0 && least > best_score) break;
      if (!grid.rows_may_hold(r, y)) continue;
      const int x = grid.first_free(r, x_min, y, x_max, hint);
      if (x < 0) continue;
      const double score = rule == Rule::kBottomLeft  ? y + 1e-6 * x
                           : rule == Rule::kNarrowest ? y + 1e-6 * (x + r.width)
                                                      : (y + r.height) + 0.5 * (x + r.width);
      if (score < best_score) best = {static_cast<int>(q), x, y}, best_score = score;
      if (rule != Rule::kCorner) break;
    }
  }
  return best;
}

/// One first-fit pass over the parts in \p order: each on the first sheet with room, there
/// at the best position (\p rule) over its orientations.
struct Pass {
  std::vector<Placement> placements;
  std::vector<int> unplaced;
  std::vector<double> sheet_area;  ///< parts' area per sheet [mm^2]
  std::vector<SheetGrid> grids;
  int sheets() const { return static_cast<int>(sheet_area.size()); }
  /// Fewer parts left out, then fewer sheets, then less on the last sheet.
  bool better_than(const Pass& b) const {
    if (unplaced.size() != b.unplaced.size()) return unplaced.size() < b.unplaced.size();
    if (sheets() != b.sheets()) return sheets() < b.sheets();
    return sheets() > 0 && sheet_area.back() < b.sheet_area.back() - 1e-6;
  }
};

/// Puts part \p i at \p spot of sheet \p s (raster \p r).
void put(Pass& pass, int i, int s, const Raster& r, const Spot& spot, double area, double cell) {
  pass.grids[s].mark(r, spot.x, spot.y);
  // Turned part frame -> sheet: shift so the raster's corner lands on its grid cell.
  const Vec2 shift = Vec2(spot.x * cell, spot.y * cell) - r.corner;
  pass.placements[i] = {s, r.angle, shift};
  if (pass.sheet_area.size() <= static_cast<std::size_t>(s)) pass.sheet_area.resize(s + 1, 0.0);
  pass.sheet_area[s] += area;
}

/// The most cells a sheet's occupancy grid has: 2000 x 2000 mm at the 1 mm step.
constexpr double kMaxCells = 4e6;

/// The far corner's pass on the half-cell grid (nest_parts) runs only where the last sheet
/// holds at most this share of a sheet's usable area in parts [-]: where it saved a sheet, the
/// last one held 0.8-4.5 %; on the scaling benchmark's Spot with 1 and 2 Catmull-Clark steps
/// (29.5 and 16.1 %) it saved none, for 0.7 and 2.8 s more.
constexpr double kEmptiableLastSheet = 0.1;

/// \p turns: per part, the turns to try (default: its quarter turns, Prepared::quarters),
/// rasterised on a grid of o.step.
Pass place_in_order(const std::vector<int>& order, const std::vector<Prepared>& parts,
                    const LayoutOptions& o, Rule rule, const std::vector<Turned>* turns = nullptr) {
  const double cell = o.step;
  Pass pass;
  pass.placements.resize(parts.size());
  for (int i : order) {
    const Prepared& part = parts[i];
    if (!part.fits) {
      pass.unplaced.push_back(i);
      continue;
    }
    bool placed = false;
    for (std::size_t s = 0; s <= pass.grids.size() && !placed; ++s) {
      const bool fresh = s == pass.grids.size();
      if (fresh) pass.grids.emplace_back(o.size_of(static_cast<int>(s)), cell);
      const Turned& turned = turns ? (*turns)[i] : part.quarters;
      const Spot spot = find_spot(pass.grids[s], turned, rule, o);
      if (spot.raster < 0) {
        // An offcut this part does not fit stays open for the parts after it (nest_parts
        // drops it if none takes it); a fresh stock sheet that does not take it, no sheet does.
        if (fresh && s >= o.offcuts.size()) {
          pass.grids.pop_back();
          break;
        }
        continue;
      }
      put(pass, i, static_cast<int>(s), turned.rasters[spot.raster], spot, part.area, cell);
      placed = true;
    }
    if (!placed) pass.unplaced.push_back(i);
  }
  pass.sheet_area.resize(pass.grids.size(), 0.0);
  return pass;
}

/// Places part \p i on the first of sheets [0, \p sheets) with room, turned in 10 degree steps.
bool place_turned(Pass& pass, int i, const Prepared& part, int sheets, const LayoutOptions& o) {
  const Turned t = turned(part, 36, o.step);
  for (int s = 0; s < sheets; ++s) {
    const Spot spot = find_spot(pass.grids[s], t, Rule::kBottomLeft, o);
    if (spot.raster < 0) continue;
    put(pass, i, s, t.rasters[spot.raster], spot, part.area, o.step);
    return true;
  }
  return false;
}

/// Tries to empty the last sheet: its parts, largest first, go into the gaps of the earlier
/// sheets, turned in 10 degree steps (the passes try only quarter turns of the minimum
/// rectangle). All or nothing: the pass changes only if every part of the last sheet finds a
/// place. (Taking a sheet's small parts off to make room for a large one and placing them
/// again was tried as well: on the benchmark's jobs no large part fitted even then.)
void empty_last_sheet(Pass& pass, const std::vector<Prepared>& parts, const LayoutOptions& o) {
  if (pass.sheets() < 2) return;
  const int last = pass.sheets() - 1;
  std::vector<int> on_last;
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (parts[i].fits && pass.placements[i].sheet == last) on_last.push_back(static_cast<int>(i));
  std::stable_sort(on_last.begin(), on_last.end(),
                   [&](int a, int b) { return parts[a].area > parts[b].area; });
  Pass trial = pass;
  trial.grids.pop_back();
  trial.sheet_area.pop_back();
  for (int i : on_last)
    if (!place_turned(trial, i, parts[i], last, o)) return;
  pass = std::move(trial);
}

}  // namespace

void check_sheets(const LayoutOptions& o) {
  if (!(o.margin >= 0) || !(o.spacing >= 0))
    throw InvalidInput("--margin and --spacing must be >= 0 mm");
  for (int k = 0; k <= static_cast<int>(o.offcuts.size()); ++k) {  // the offcuts, the stock
    const Vec2 size = o.size_of(k);
    if (!(size.x() > 0) || !(size.y() > 0))
      throw InvalidInput("--sheet: every sheet's width and height must be > 0 mm");
    if (2 * o.margin >= std::min(size.x(), size.y())) {
      std::ostringstream os;
      os << "--sheet: the " << size.x() << " x " << size.y()
         << " mm sheet has no room inside margins of " << o.margin
         << " mm (--margin, plus the plate's thickness for teeth, or in paper a glue "
         << "tab's height): each side must be over " << 2 * o.margin << " mm";
      throw InvalidInput(os.str());
    }
    // Parts keep the spacing apart: each takes half of it on every side.
    const double inside = std::min(size.x(), size.y()) - 2 * o.margin;
    if (o.spacing >= inside) {
      std::ostringstream os;
      os << "--spacing " << o.spacing << " mm leaves no room for a part on the " << size.x()
         << " x " << size.y() << " mm sheet, whose narrower side is " << inside
         << " mm inside its margins";
      throw InvalidInput(os.str());
    }
  }
}

LayoutResult nest_parts(const std::vector<Polygon2>& outlines, const LayoutOptions& options) {
  // A grid cell of the step asked, or coarser where a sheet would have more than kMaxCells of
  // them (a 10 x 10 m sheet at 1 mm: 10^8 cells, about 0.9 GB per grid and pass).
  if (!(options.step > 0)) throw InvalidInput("layout step must be > 0 mm");
  LayoutOptions o = options;
  for (int k = 0; k <= static_cast<int>(o.offcuts.size()); ++k) {  // the offcuts, the stock
    const Vec2 size = o.size_of(k);
    if (size.x() > 0 && size.y() > 0 && std::isfinite(size.x() * size.y()))
      o.step = std::max(o.step, std::sqrt(size.x() * size.y() / kMaxCells));
  }
  check_sheets(o);
  const int n = static_cast<int>(outlines.size());
  std::vector<Prepared> parts(n);
  for_each_index(n, hardware_threads(), [&](int i) {
    const Polygon2& outline = outlines[i];
    Prepared& p = parts[i];
    p.area = std::abs(polygon_area(outline));
    if (outline.size() < 3 || !fits_sheet(outline, o)) return;
    p.fits = true;
    const auto grown = polygon_offset({outline}, 0.5 * o.spacing);
    const Polygon2 inflated = grown.empty() ? outline : grown.front();
    p.grown_area = std::abs(polygon_area(inflated));
    const MinRect rect = min_area_rect(outline);
    p.rect_angle = rect.angle;
    p.outline = outline;
    p.inflated = inflated;
    p.rect_area = rect.width * rect.height;
    p.length = std::max(rect.width, rect.height);
    p.quarters = turned(p, 4, o.step);
  });
  LayoutResult result;
  // Bounds on the sheets any nesting needs: the parts' area over the usable area, and with the
  // spacing (the parts grown by half of it are disjoint and lie in the usable area grown alike).
  double fitting_area = 0, grown_area = 0;  // of the parts that fit a sheet [mm^2]
  for (const Prepared& p : parts)
    if (p.fits) fitting_area += p.area, grown_area += p.grown_area;
  // With offcuts: the fewest sheets whose areas add up to it, the largest first (offcuts larger
  // than a stock sheet, then stock sheets; a smaller offcut never beats another stock sheet).
  // A sheet's usable area, its sides grown by \p grow [mm^2].
  auto usable_of = [&](const Vec2& size, double grow) {
    return (size.x() - 2 * o.margin + grow) * (size.y() - 2 * o.margin + grow);
  };
  auto sheets_for = [&](double area, double grow) {
    const double stock = usable_of(o.size_of(-1), grow);
    std::vector<double> larger;
    for (const Vec2& offcut : o.offcuts)
      if (usable_of(offcut, grow) > stock) larger.push_back(usable_of(offcut, grow));
    std::sort(larger.rbegin(), larger.rend());
    int k = 0;
    for (double a : larger)
      if (area > 0) area -= a, ++k;
    if (area > 0) k += static_cast<int>(std::ceil(area / stock - 1e-9));
    return k;
  };
  result.sheets_lower_bound = sheets_for(fitting_area, 0);
  result.spaced_fill = grown_area / usable_of(o.size_of(-1), o.spacing);
  result.sheets_lower_bound_spaced = sheets_for(grown_area, o.spacing);
  // Largest area first, bottom-left. While that needs more sheets than the spaced bound, also
  // the parts with the largest minimum rectangle first (long thin and curved parts, which
  // otherwise come last and open sheets of their own) and the longest first, each with both
  // placing rules, and then passes that put the parts the best one left on its last sheet
  // first; every pass then tries to empty its last sheet into the others' gaps. The best pass
  // is kept.
  auto order_by = [&](auto key) {
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) > key(b); });
    return order;
  };
  const std::vector<int> by_area = order_by([&](int i) { return parts[i].area; });
  Pass best = place_in_order(by_area, parts, o, Rule::kBottomLeft);
  // Each extra pass costs about as much as the first: all of them (up to 14, on all cores)
  // only where parts x sheets is at most 2000 (about 2 s on 2 cores; Spot at 500 mm with 4
  // Catmull-Clark steps, 578 parts on 10 sheets, took 13.6 s for one pass and 57 s for all),
  // else only the two other orders, bottom-left.
  const bool cheap = static_cast<double>(n) * best.sheets() <= kCheapNest;
  if (best.sheets() > result.sheets_lower_bound_spaced) {
    const std::vector<int> by_rect = order_by([&](int i) { return parts[i].rect_area; });
    const std::vector<int> by_length = order_by([&](int i) { return parts[i].length; });
    // Each extra pass: its order and rule; no order: the first pass again (for its last sheet).
    using Extra = std::vector<std::pair<const std::vector<int>*, Rule>>;
    const Extra extra = cheap
                            ? Extra{{&by_area, Rule::kCorner},   {nullptr, Rule::kBottomLeft},
                                    {&by_rect, Rule::kCorner},   {&by_rect, Rule::kBottomLeft},
                                    {&by_length, Rule::kCorner}, {&by_length, Rule::kBottomLeft},
                                    {&by_area, Rule::kNarrowest}}
                            : Extra{{&by_rect, Rule::kBottomLeft}, {&by_length, Rule::kBottomLeft}};
    std::vector<Pass> more(extra.size());
    for_each_index(static_cast<int>(more.size()), hardware_threads(), [&](int k) {
      const auto& [order, rule] = extra[k];
      more[k] = order ? place_in_order(*order, parts, o, rule) : best;
      if (cheap) empty_last_sheet(more[k], parts, o);
    });
    for (Pass& p : more)
      if (p.better_than(best)) best = std::move(p);
    // Parts that ended on the last sheet first, for a few rounds.
    std::vector<int> order = by_area;
    for (int round = 0; cheap && round < 4 && best.sheets() > result.sheets_lower_bound_spaced;
         ++round) {
      const int last = best.sheets() - 1;
      std::vector<int> front, rest;
      for (int i : order)
        (parts[i].fits && best.placements[i].sheet == last ? front : rest).push_back(i);
      front.insert(front.end(), rest.begin(), rest.end());
      if (front == order) break;  // the same parts first again: the same passes
      order = std::move(front);
      std::vector<Pass> tried(2);
      for_each_index(2, hardware_threads(), [&](int k) {
        tried[k] = place_in_order(order, parts, o, k == 0 ? Rule::kCorner : Rule::kBottomLeft);
        empty_last_sheet(tried[k], parts, o);
      });
      for (Pass& p : tried)
        if (p.better_than(best)) best = std::move(p);
    }
  }
  // Still over the spaced bound: once more, largest first, on a grid of half the cell (each
  // cell a part's outline touches is taken, so the gaps lose half as much; about 4 times the
  // cost of a pass), bottom-left, and where that saves no sheet by the far corner with the
  // last sheet emptied into the others (which costs more: every row is tried, and the last
  // sheet's parts turned in 10 degree steps); kept only where it saves a sheet.
  // stanford-bunny from its triangles: 365 parts, 4 of them on a second sheet (0.1 % used) at
  // 1 mm cells, all on one at 0.5 mm, bottom-left. The far corner's pass saves where
  // bottom-left does not: 3 sheets, the spaced bound, instead of 4 for Spot's parts from its
  // triangles (tests/data) on 325 and 330 x 250 sheets, and in a whole run for
  // spot_quadrangulated in 4 mm plywood at 300 mm on 400 x 300 (460 parts); of 58 jobs (the
  // shared meshes' parts in plywood at 300 mm, read back from their sheets and nested again
  // on 300 x 300, 400 x 300 and 600 x 450 sheets) it saved 2 sheets of 165, for 4-10 % more
  // nesting time in all. Only where the grown parts would fill the sheets but one no fuller
  // than the fullest sheets the passes reach (kFullestSheet): else it cannot save one, and
  // costs (Amo on 300 x 250 sheets: 0.7 s more for the same 4 sheets).
  if (cheap && best.sheets() > result.sheets_lower_bound_spaced &&
      !too_full_for_one_fewer(result.spaced_fill, best.sheets())) {
    LayoutOptions fine = o;
    fine.step = 0.5 * o.step;
    std::vector<Turned> quarters(n);
    for_each_index(n, hardware_threads(), [&](int i) {
      if (parts[i].fits) quarters[i] = turned(parts[i], 4, fine.step);
    });
    // One pass on the fine grid by \p rule (its last sheet then emptied into the others where
    // \p empty), taken where it saves a sheet.
    auto saves_a_sheet = [&](Rule rule, bool empty) {
      Pass finer = place_in_order(by_area, parts, fine, rule, &quarters);
      if (empty) empty_last_sheet(finer, parts, fine);
      if (finer.unplaced.size() > best.unplaced.size() || finer.sheets() >= best.sheets())
        return false;
      best = std::move(finer);
      return true;
    };
    const double last_share = best.sheet_area.back() / usable_of(o.size_of(best.sheets() - 1), 0);
    if (!saves_a_sheet(Rule::kBottomLeft, false) && last_share <= kEmptiableLastSheet)
      saves_a_sheet(Rule::kCorner, true);
  }
  // Offcuts no part took are not used: the sheets are numbered without them.
  std::vector<char> used(best.sheets(), 0);
  for (const Placement& at : best.placements)
    if (at.sheet >= 0) used[at.sheet] = 1;
  std::vector<int> renumbered(best.sheets(), -1);
  std::vector<double> sheet_area;
  for (int k = 0; k < best.sheets(); ++k)
    if (used[k]) {
      renumbered[k] = static_cast<int>(result.sheet_sizes.size());
      result.sheet_sizes.push_back(o.size_of(k));
      sheet_area.push_back(best.sheet_area[k]);
    }
  for (Placement& at : best.placements)
    if (at.sheet >= 0) at.sheet = renumbered[at.sheet];
  result.placements = std::move(best.placements);
  result.unplaced = std::move(best.unplaced);
  std::sort(result.unplaced.begin(), result.unplaced.end());
  for (int i : result.unplaced)
    if (outlines[i].size() < 3 || !(parts[i].area > 0)) result.empty.push_back(i);
  result.sheets = static_cast<int>(result.sheet_sizes.size());
  if (result.sheets == 0 && n > 0 && static_cast<int>(result.empty.size()) == n)
    throw InvalidInput(
        "every part has nothing left once its slots and mitres are cut (the shape is thinner "
        "than the sheets, or too small for them); use a larger --size or "
        "a thinner --material");
  if (result.sheets == 0 && n > 0) {
    // Nothing fits: the sheet is the problem, not the parts. Say what would fit the smallest.
    double need = 1e300;
    for (const Polygon2& part : outlines) {
      if (part.size() < 3) continue;
      const MinRect r = min_area_rect(part);
      need = std::min(need, std::min(r.width, r.height));
    }
    std::ostringstream os;
    os << "no part fits a " << o.sheet_width << " x " << o.sheet_height << " mm sheet with "
       << o.margin << " mm margins";
    if (need < 1e300)
      os << " (the narrowest part is " << std::ceil(need) << " mm wide, teeth included)";
    os << "; use a larger --sheet, a smaller --size, or finer quads (a part larger than the "
          "sheet is split between its quads, one quad is not)";
    throw InvalidInput(os.str());
  }
  double total = 0, whole = 0;
  for (int k = 0; k < result.sheets; ++k) {
    const double area = result.sheet_sizes[k].x() * result.sheet_sizes[k].y();
    total += sheet_area[k], whole += area;
    result.sheet_utilization.push_back(sheet_area[k] / area);
  }
  if (o.offcuts.empty()) whole = result.sheets * o.sheet_width * o.sheet_height;  // as it was
  result.utilization = result.sheets > 0 ? total / whole : 0.0;
  return result;
}

}  // namespace kerfab
