#include "kerfab/io/sheet_files.h"

#include <cstdio>
#include <fstream>

#include "kerfab/core/errors.h"

namespace kerfab {

std::filesystem::path sheet_file(const std::filesystem::path& cut_dir, int sheet,
                                 const std::string& extension) {
  std::error_code ec;
  std::filesystem::create_directories(cut_dir, ec);
  if (ec) throw IoError("cannot create " + cut_dir.string() + ": " + ec.message());
  char name[32];
  std::snprintf(name, sizeof name, "sheet-%03d.", sheet + 1);
  return cut_dir / (name + extension);
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  if (!file) throw IoError("cannot write " + path.string());
}

}  // namespace kerfab
