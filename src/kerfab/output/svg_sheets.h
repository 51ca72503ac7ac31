#pragma once
/// \file Laser-cut sheets as SVG (docs/outputs.md): 1 user unit = 1 mm, one group per part
/// with its engraved label (blue), kerf cuts and outline (red, cut in that order: inside first).
#include <filesystem>

#include "kerfab/output/output_options.h"
#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// Writes cut/sheet-001.svg ... for a run with a layout, in \p style. \throw IoError on write
/// failure.
void write_svg_sheets(const RunResult& run, const SheetStyle& style,
                      const std::filesystem::path& cut_dir);

}  // namespace kerfab
