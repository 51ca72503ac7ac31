#pragma once
/// \file Laser-cut sheets as DXF (AutoCAD R12 ASCII, which every laser and CAD program reads):
/// millimetres declared in the header ($INSUNITS 4, $MEASUREMENT 1), outlines as closed
/// polylines on layer CUT, kerf cuts as lines on layer KERF, engraved labels as lines on layer
/// LABEL; the same geometry and order as the SVG sheets, y pointing up.
#include <filesystem>

#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// Writes cut/sheet-001.dxf ... for a run with a layout. \throw IoError on write failure.
void write_dxf_sheets(const RunResult& run, const std::filesystem::path& cut_dir);

}  // namespace kerfab
