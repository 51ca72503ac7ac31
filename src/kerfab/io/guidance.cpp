#include "kerfab/io/guidance.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "kerfab/core/errors.h"

namespace kerfab {

std::vector<EdgeGuidance> read_guidance(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw IoError("guidance file cannot be opened: " + path.string());
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput("guidance file is not valid JSON: " + path.string() + ": " + e.what());
  }
  if (!doc.is_object())
    throw InvalidInput("guidance file must hold a JSON object with 'bendable'/'stiff': " +
                       path.string());
  std::vector<EdgeGuidance> out;
  for (const auto& [key, value] : doc.items()) {
    if (key != "bendable" && key != "stiff")
      throw InvalidInput("guidance file has unknown key '" + key +
                         "' (expected 'bendable' or 'stiff'): " + path.string());
    if (!value.is_array())
      throw InvalidInput("guidance '" + key +
                         "' must be a list of [v0, v1] pairs: " + path.string());
    for (const auto& pair : value) {
      if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number_integer() ||
          !pair[1].is_number_integer())
        throw InvalidInput("guidance '" + key + "' entry " + pair.dump() +
                           " is not a pair of vertex indices: " + path.string());
      out.push_back({pair[0].get<int>(), pair[1].get<int>(), key == "bendable"});
    }
  }
  return out;
}

}  // namespace kerfab
