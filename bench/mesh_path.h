#pragma once
// Where a benchmark finds a mesh: in the repository first (tests/data, examples/spot), then in
// the optional collection beside it. Empty when it is nowhere.
#include <filesystem>
#include <string>

namespace kerfab::bench {

inline std::string mesh_path(const std::string& name) {
  for (const std::filesystem::path& dir :
       {std::filesystem::path(KERFAB_TEST_DATA), std::filesystem::path(KERFAB_EXAMPLE_DIR) / "spot",
        std::filesystem::path(KERFAB_SHARED_MESHES)})
    if (std::filesystem::exists(dir / name)) return (dir / name).string();
  return {};
}

}  // namespace kerfab::bench
