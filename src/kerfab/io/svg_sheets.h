#pragma once
/// \file Laser-cut sheets as SVG (shared/OUTPUTS.md): 1 user unit = 1 mm, one group per part
/// with its engraved label (blue), kerf cuts and outline (red, cut in that order: inside first).
#include <filesystem>

#include "kerfab/pipeline.h"

namespace kerfab {

/// Writes cut/sheet-001.svg ... for a run with a layout. \throw IoError on write failure.
/// Colours and stroke come from run.options.style.
void write_svg_sheets(const RunResult& run, const std::filesystem::path& cut_dir);

}  // namespace kerfab
