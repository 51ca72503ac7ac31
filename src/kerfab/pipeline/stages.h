#pragma once
/// \file The stages of a run, in order: the one list behind the stage clock, `--stop-after`
/// and the report's timings.
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace kerfab {

enum class Stage {
  kLoad,
  kPrepare,
  kQuads,
  kBending,
  kStrips,
  kFlatten,
  kJoints,
  kKerf,
  kResolve,
  kLayout,
  kAssembly,
  kQuality
};

inline constexpr std::array<std::string_view, 12> kStageNames = {
    "load",   "prepare", "quads",  "bending",  "strips",  "flatten",
    "joints", "kerf",    "resolve", "layout", "assembly", "quality"};

inline std::string_view stage_name(Stage stage) { return kStageNames[static_cast<int>(stage)]; }

/// The stage names in order, as strings (for option parsers and reports).
inline const std::vector<std::string>& stage_names() {
  static const std::vector<std::string> names(kStageNames.begin(), kStageNames.end());
  return names;
}

}  // namespace kerfab
