#pragma once
/// \file The assembly aid: for every part, its sheet and the parts it joins, with the shared
/// border length, as JSON (in the report) and as a small HTML page (cut/assembly.html).
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "kerfab/pipeline.h"

namespace kerfab {

/// Per part: neighbour part -> total shared border length [mm] (a part may join itself where a
/// loop was cut open).
std::vector<std::map<int, double>> part_neighbours(const RunResult& run);

nlohmann::json make_assembly_json(const RunResult& run);

/// Writes cut/assembly.html. \throw IoError on failure.
void write_assembly_page(const RunResult& run, const std::filesystem::path& cut_dir);

}  // namespace kerfab
