#pragma once
/// \file Shared by the sheet writers: file names and writing a whole file.
#include <filesystem>
#include <string>

namespace kerfab {

/// cut_dir / "sheet-NNN.<extension>" for the 0-based \p sheet, creating cut_dir.
/// \throw IoError the directory cannot be created.
std::filesystem::path sheet_file(const std::filesystem::path& cut_dir, int sheet,
                                 const std::string& extension);

/// Writes \p text to \p path. \throw IoError on failure.
void write_text_file(const std::filesystem::path& path, const std::string& text);

}  // namespace kerfab
