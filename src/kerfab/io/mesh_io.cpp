#include "kerfab/io/mesh_io.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <fstream>
#include <iostream>
#include <sstream>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

/// Captures OpenMesh's diagnostic streams for the lifetime of the guard instead of letting them
/// reach the user's terminal; the reader's complaints become our one-line errors.
class OpenMeshLogCapture {
 public:
  OpenMeshLogCapture() {
    ::omerr().disconnect(std::cerr);
    ::omlog().disconnect(std::clog);
    ::omout().disconnect(std::cout);
    ::omerr().connect(log_);
    ::omlog().connect(log_);
    ::omout().connect(log_);
  }
  ~OpenMeshLogCapture() {
    ::omerr().flush();
    ::omerr().disconnect(log_);
    ::omlog().disconnect(log_);
    ::omout().disconnect(log_);
    ::omerr().connect(std::cerr);
    ::omlog().connect(std::clog);
    ::omout().connect(std::cout);
  }
  OpenMeshLogCapture(const OpenMeshLogCapture&) = delete;
  OpenMeshLogCapture& operator=(const OpenMeshLogCapture&) = delete;
  std::string text() {
    ::omerr().flush();
    ::omlog().flush();
    return log_.str();
  }

 private:
  std::ostringstream log_;
};

int count_occurrences(const std::string& text, const std::string& needle) {
  int n = 0;
  for (auto pos = text.find(needle); pos != std::string::npos; pos = text.find(needle, pos + 1))
    ++n;
  return n;
}

}  // namespace

PolyMesh read_mesh(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError("mesh file not found: " + name);
  if (std::filesystem::is_directory(path, ec)) throw IoError("mesh path is a directory: " + name);
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw IoError("mesh file cannot be opened: " + name);
  }
  const std::string ext = path.extension().string();
  std::string lower;
  for (char c : ext) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower != ".obj" && lower != ".off" && lower != ".ply" && lower != ".stl")
    throw IoError("unsupported mesh format '" + ext + "' (use .obj, .off, .ply or .stl): " + name);

  PolyMesh mesh;
  std::string log;
  bool ok = false;
  {
    OpenMeshLogCapture capture;
    OpenMesh::IO::Options opt;
    ok = OpenMesh::IO::read_mesh(mesh, name, opt);
    log = capture.text();
  }
  if (!ok) {
    std::string reason = log.substr(0, log.find('\n'));
    throw IoError("cannot read mesh " + name + (reason.empty() ? "" : ": " + reason));
  }
  if (mesh.n_faces() == 0) throw InvalidInput("mesh has no faces: " + name);

  const int repeated = count_occurrences(log, "equal vertices");
  const int invalid = count_occurrences(log, "invalid vertex index");
  if (repeated > 0)
    throw InvalidInput("mesh has " + std::to_string(repeated) +
                       " degenerate face(s) that repeat a vertex: " + name);
  if (invalid > 0)
    throw InvalidInput("mesh has " + std::to_string(invalid) +
                       " face(s) with an out-of-range vertex index: " + name);
  std::size_t nonmanifold = 0;
  for (auto f : mesh.faces())
    if (mesh.status(f).fixed_nonmanifold()) ++nonmanifold;
  if (nonmanifold > 0)
    throw InvalidInput(
        "mesh is not manifold (" + std::to_string(nonmanifold) +
        " face(s) on a non-manifold or inconsistently oriented edge/vertex): " + name);
  return mesh;
}

void write_mesh(const PolyMesh& mesh, const std::filesystem::path& path) {
  bool ok = false;
  {
    OpenMeshLogCapture capture;
    OpenMesh::IO::Options opt;
    ok = OpenMesh::IO::write_mesh(mesh, path.string(), opt, 10);
  }
  if (!ok) throw IoError("cannot write mesh " + path.string());
}

}  // namespace kerfab
