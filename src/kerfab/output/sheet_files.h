#pragma once
/// \file Shared by the sheet writers: what goes on a sheet, file names, writing a whole file.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// A fold line as placed on a sheet.
struct PlacedFold {
  std::vector<Vec2> points;
  bool mountain = false;
};

/// Dash patterns of fold lines on printed sheets (SVG, PDF, previews) [mm]: mountain dash-dot,
/// valley dashed, as papercraft sheets draw them.
inline constexpr std::array<double, 4> kMountainDash = {3.0, 1.0, 0.5, 1.0};
inline constexpr std::array<double, 2> kValleyDash = {2.0, 1.0};

/// One part as placed on a sheet, in sheet millimetres with y up; every writer draws these, in
/// this order (inside first): engraving, kerf cuts, fold lines, outline.
struct PlacedPart {
  int part = -1;
  std::vector<Label> labels;                   ///< upright, origin on the sheet
  std::vector<std::array<Vec2, 2>> engraving;  ///< the labels' strokes
  std::vector<std::array<Vec2, 2>> kerf;       ///< kerf cuts
  std::vector<PlacedFold> folds;               ///< paper: score/fold lines
  Polygon2 outline;                            ///< the laser path (closed)
};

/// The parts on sheet \p sheet (0-based) of a run with a layout, in part order.
std::vector<PlacedPart> sheet_parts(const RunResult& run, int sheet);

/// cut_dir / "sheet-NNN.<extension>" for the 0-based \p sheet, creating cut_dir.
/// \throw IoError the directory cannot be created.
std::filesystem::path sheet_file(const std::filesystem::path& cut_dir, int sheet,
                                 const std::string& extension);

/// Writes \p text to \p path. \throw IoError on failure.
void write_text_file(const std::filesystem::path& path, const std::string& text);

}  // namespace kerfab
