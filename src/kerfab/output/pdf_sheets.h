#pragma once
/// \file Cut sheets through cairo: a PDF per sheet (same geometry as the SVG/DXF, page size =
/// sheet size), a PNG preview per sheet (lines drawn thick enough to see) and a contact sheet
/// of all sheets.
#include <filesystem>

#include "kerfab/output/output_options.h"
#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// Writes cut/sheet-NNN.pdf. \throw IoError on failure.
void write_pdf_sheets(const RunResult& run, const SheetStyle& style,
                      const std::filesystem::path& cut_dir);

/// Writes cut/sheet-NNN.png (\p pixels_per_mm) and cut/contact-sheet.png.
/// \throw IoError on failure.
void write_sheet_previews(const RunResult& run, const SheetStyle& style,
                          const std::filesystem::path& cut_dir, double pixels_per_mm = 2.5);

}  // namespace kerfab
