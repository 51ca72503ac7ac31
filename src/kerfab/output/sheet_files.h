#pragma once
/// \file Shared by the sheet writers: what goes on a sheet, file names, writing a whole file.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// One part as placed on a sheet, in sheet millimetres with y up; every writer draws these, in
/// this order (inside first): engraving, kerf cuts, outline.
struct PlacedPart {
  int part = -1;
  std::vector<Label> labels;                   ///< upright, origin on the sheet
  std::vector<std::array<Vec2, 2>> engraving;  ///< the labels' strokes
  std::vector<std::array<Vec2, 2>> kerf;       ///< kerf cuts
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
