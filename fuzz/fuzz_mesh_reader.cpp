// libFuzzer target for the mesh readers (scripts/fuzz.sh builds one per format with
// KERFAB_FUZZ_EXT set to .obj, .off, .ply or .stl). Each input is written to a file of that
// format and read: kerfab's errors (InvalidInput, IoError) are the expected answer to garbage;
// anything else, a crash or a sanitizer report is a finding.
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "kerfab/core/errors.h"
#include "kerfab/io/mesh_io.h"

#ifndef KERFAB_FUZZ_EXT
#error "define KERFAB_FUZZ_EXT (\".obj\", \".off\", \".ply\" or \".stl\")"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path =
      "/tmp/kerfab-fuzz-" + std::to_string(::getpid()) + KERFAB_FUZZ_EXT;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const kerfab::PolyMesh mesh = kerfab::read_mesh(path);
    for (auto v : mesh.vertices()) {  // what the reader promises: finite points
      const auto& p = mesh.point(v);
      if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) __builtin_trap();
    }
  } catch (const kerfab::InvalidInput&) {
  } catch (const kerfab::IoError&) {
  }
  return 0;
}
