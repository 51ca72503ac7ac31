#pragma once
// Small helpers shared by the tests: temporary files and where the real meshes are.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "kerfab/core/mesh.h"

namespace kerfab::test {

/// A real mesh kept in the repository: tests/data/ or the bundled example examples/spot/.
inline std::filesystem::path real_mesh(const std::string& name) {
  const std::filesystem::path data = std::filesystem::path(KERFAB_TEST_DATA) / name;
  if (std::filesystem::exists(data)) return data;
  return std::filesystem::path(KERFAB_EXAMPLE_DIR) / "spot" / name;
}

/// The optional larger collection beside the repository (../shared/data/meshes).
inline std::filesystem::path shared_meshes() { return KERFAB_SHARED_MESHES; }
inline bool have_shared_meshes() { return std::filesystem::is_directory(shared_meshes()); }

/// Optional extra checks on ../shared/data/meshes: skipped, not failed, where it is absent.
#define KERFAB_SKIP_WITHOUT_SHARED_MESHES()                                                  \
  do {                                                                                       \
    if (!::kerfab::test::have_shared_meshes())                                               \
      GTEST_SKIP() << "optional check: " << ::kerfab::test::shared_meshes() << " is absent"; \
  } while (0)

/// A fresh empty directory under the test temp dir, named after the running test.
/// Under a folder of its build tree's own: two suites running at once on one machine (a clean
/// clone's beside a working copy's) each cleared the other's folder of the same test
/// (OutputSafety.ARerunKeepsTheUsersOwnFilesInsideAnEarlierRun failed so, 2026-12-05).
inline std::filesystem::path fresh_dir(const std::string& tag = "") {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  static const std::string tree = [] {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::string where = ec ? std::string(KERFAB_TEST_DATA) : exe.parent_path().string();
    return "tree-" + std::to_string(std::hash<std::string>{}(where) % 1000000007u);
  }();
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / "kerfab_tests" / tree /
      (std::string(info->test_suite_name()) + "." + info->name() + tag);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::filesystem::path write_text(const std::filesystem::path& path,
                                        const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

/// Best sum of weight[e] over selections of quad-mesh edges with no two consecutive edges of a
/// quad, by enumerating all 2^|E| subsets (small meshes only, |E| <= 30).
inline double exhaustive_packing_optimum(const PolyMesh& m, const std::vector<double>& weight) {
  const int n = static_cast<int>(m.n_edges());
  std::vector<std::pair<int, int>> conflicts;
  for (auto f : m.faces()) {
    const auto e = quad_edges(m, f);
    for (int k = 0; k < 4; ++k) conflicts.emplace_back(e[k], e[(k + 1) % 4]);
  }
  double best = 0;
  for (std::uint64_t mask = 0; mask < (std::uint64_t{1} << n); ++mask) {
    bool ok = true;
    for (auto [a, b] : conflicts)
      if ((mask >> a & 1) && (mask >> b & 1)) {
        ok = false;
        break;
      }
    if (!ok) continue;
    double f = 0;
    for (int i = 0; i < n; ++i)
      if (mask >> i & 1) f += weight[i];
    best = std::max(best, f);
  }
  return best;
}

}  // namespace kerfab::test
