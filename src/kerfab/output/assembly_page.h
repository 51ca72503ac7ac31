#pragma once
/// \file The assembly aid as a small HTML page (cut/assembly.html): for every part, its sheet
/// and the parts it joins, with the shared border length.
#include <filesystem>

#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// Writes cut/assembly.html. \throw IoError on failure.
void write_assembly_page(const RunResult& run, const std::filesystem::path& cut_dir);

}  // namespace kerfab
