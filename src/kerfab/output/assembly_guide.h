#pragma once
/// \file The assembly guide, DIR/assembly/: index.html (the model in 3D, step by step in the
/// assembly order, each part's number, sheet and neighbours; opens from the file system with no
/// server and no network), the data it shows (model.js), the three.js files it needs (Debian's
/// libjs-three, built into kerfab) and steps.pdf (one small picture per step, to print).
#include <filesystem>

#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// Writes the guide into \p dir (created). \pre the run has its layout and assembly order.
/// \throw IoError a file cannot be written.
void write_assembly_guide(const RunResult& run, const std::filesystem::path& dir);

}  // namespace kerfab
