#include "kerfab/io/guidance.h"

#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "kerfab/core/errors.h"

namespace kerfab {

Guidance read_guidance(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw IoError("guidance file not found: " + path.string());
  if (!std::filesystem::is_regular_file(path, ec))
    throw IoError("guidance path is not a regular file: " + path.string());
  std::ifstream in(path);
  if (!in) throw IoError("guidance file cannot be opened: " + path.string());
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput("guidance file is not valid JSON: " + path.string() + ": " + e.what());
  }
  if (!doc.is_object())
    throw InvalidInput(
        "guidance file must hold a JSON object with 'bendable', 'stiff', 'split' or 'merge': " +
        path.string());
  Guidance out;
  for (const auto& [key, value] : doc.items()) {
    if (key != "bendable" && key != "stiff" && key != "split" && key != "merge")
      throw InvalidInput("guidance file has unknown key '" + key +
                         "' (expected 'bendable', 'stiff', 'split' or 'merge'): " + path.string());
    if (!value.is_array())
      throw InvalidInput("guidance '" + key +
                         "' must be a list of [v0, v1] pairs: " + path.string());
    for (const auto& pair : value) {
      auto index = [](const nlohmann::json& v) {
        return v.is_number_unsigned() &&
               v.get<std::uint64_t>() <=
                   static_cast<std::uint64_t>(std::numeric_limits<int>::max());
      };
      if (!pair.is_array() || pair.size() != 2 || !index(pair[0]) || !index(pair[1]))
        throw InvalidInput("guidance '" + key + "' entry " + pair.dump() +
                           " is not a pair of vertex indices (integers 0 .. " +
                           std::to_string(std::numeric_limits<int>::max()) + "): " + path.string());
      const std::array<int, 2> v = {pair[0].get<int>(), pair[1].get<int>()};
      if (key == "split")
        out.split.push_back(v);
      else if (key == "merge")
        out.merge.push_back(v);
      else
        out.edges.push_back({v[0], v[1], key == "bendable"});
    }
  }
  return out;
}

}  // namespace kerfab
