#pragma once
/// \file User guidance file (paper Sec. 3.5): edges forced bendable or stiff.
#include <filesystem>
#include <vector>

#include "kerfab/core/guidance.h"

namespace kerfab {

/// Reads a guidance file of the form
///   {"bendable": [[v0, v1], ...], "stiff": [[v0, v1], ...]}
/// where v0, v1 are vertex indices of the quad mesh as used (after --subdivide; the same
/// indices as in stages/bending.json). Both keys are optional.
/// \throw IoError the file cannot be read. \throw InvalidInput it is not of that form.
std::vector<EdgeGuidance> read_guidance(const std::filesystem::path& path);

}  // namespace kerfab
