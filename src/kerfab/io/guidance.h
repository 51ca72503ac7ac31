#pragma once
/// \file User guidance file (paper Sec. 3.5): edges forced bendable or stiff, strip borders to
/// insert, strips to merge sideways.
#include <filesystem>

#include "kerfab/core/guidance.h"

namespace kerfab {

/// Reads a guidance file of the form
///   {"bendable": [[v0, v1], ...], "stiff": [[v0, v1], ...],
///    "split": [[v0, v1], ...], "merge": [[v0, v1], ...]}
/// where v0, v1 are vertex indices of the quad mesh as used (after --subdivide; the same
/// indices as in stages/bending.json). Every key is optional.
/// \throw IoError the file cannot be read or is not a regular file. \throw InvalidInput it is
/// not of that form (unknown key, not a pair, an index that is not a non-negative integer that
/// fits an int).
Guidance read_guidance(const std::filesystem::path& path);

}  // namespace kerfab
