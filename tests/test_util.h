#pragma once
// Small helpers shared by the tests: temporary files and the real-mesh folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace kerfab::test {

inline std::filesystem::path shared_meshes() { return KERFAB_SHARED_MESHES; }

/// A fresh empty directory under the test temp dir, named after the running test.
inline std::filesystem::path fresh_dir(const std::string& tag = "") {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / "kerfab_tests" /
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

}  // namespace kerfab::test
