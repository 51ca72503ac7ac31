// libFuzzer target for the guidance file parser: kerfab's errors are the expected answer to
// garbage; anything else, a crash or a sanitizer report is a finding.
#include <unistd.h>

#include <climits>
#include <cstdint>
#include <fstream>
#include <string>

#include "kerfab/core/errors.h"
#include "kerfab/io/guidance.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/kerfab-fuzz-" + std::to_string(::getpid()) + ".json";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const kerfab::Guidance g = kerfab::read_guidance(path);
    for (const auto& e : g.edges)  // what the parser promises: indices that did not wrap
      if (e.v0 < 0 || e.v1 < 0) __builtin_trap();
  } catch (const kerfab::InvalidInput&) {
  } catch (const kerfab::IoError&) {
  }
  return 0;
}
