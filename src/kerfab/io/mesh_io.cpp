#include "kerfab/io/mesh_io.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "kerfab/core/errors.h"
#include "kerfab/io/orient.h"

#if defined(__SANITIZE_ADDRESS__)
/// The sanitized build's LeakSanitizer: OpenMesh's stream connects below allocate once per
/// process and are never freed, on purpose (OpenMesh keeps them); not a leak.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOpenMeshCore.so\nleak:libfontconfig.so\n";
}
/// ... and says nothing about it (the one error line stays the only line).
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }
#endif

namespace kerfab {
namespace {

/// Captures OpenMesh's diagnostic streams for the lifetime of the guard instead of letting them
/// reach the user's terminal; the reader's complaints become our one-line errors. The streams are
/// redirected once per process into one buffer: OpenMesh allocates on every connect and never
/// frees on disconnect (a leak per file read, found by the fuzzer).
class OpenMeshLogCapture {
 public:
  OpenMeshLogCapture() : log_(buffer()) {
    log_.str("");
    log_.clear();
  }
  OpenMeshLogCapture(const OpenMeshLogCapture&) = delete;
  OpenMeshLogCapture& operator=(const OpenMeshLogCapture&) = delete;
  std::string text() {
    ::omerr().flush();
    ::omlog().flush();
    ::omout().flush();
    return log_.str();
  }

 private:
  static std::ostringstream& buffer() {
    static std::ostringstream* const log = [] {
      auto* s = new std::ostringstream;  // lives as long as the process (OpenMesh holds it)
      ::omerr().disconnect(std::cerr);
      ::omlog().disconnect(std::clog);
      ::omout().disconnect(std::cout);
      ::omerr().connect(*s);
      ::omlog().connect(*s);
      ::omout().connect(*s);
      return s;
    }();
    return *log;
  }

  std::ostringstream& log_;
};

/// The triangle count in a binary STL's first 84 bytes \p head (after the 80-byte header).
std::uint32_t stl_count(const char* head) {
  std::uint32_t n = 0;
  std::memcpy(&n, head + 80, 4);
  return n;
}

/// Whether an STL file of \p size bytes starting with \p head (its first 84 bytes) is binary, as
/// OpenMesh's reader decides: its size is what the triangle count after the 80-byte header makes
/// it (84 + 50 n bytes), or it does not start with "solid". (Exporters write binary files whose
/// header starts with "solid"; read as ASCII here, their nan corners went unseen.)
bool binary_stl(const char* head, std::uintmax_t size) {
  return 84ULL + 50ULL * stl_count(head) == size || std::string(head, 5) != "solid";
}

/// binary_stl() for the file at \p path; false where it is shorter than 84 bytes.
bool binary_stl(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char head[84];
  if (!in.read(head, 84)) return false;
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return ec ? std::string(head, 5) != "solid" : binary_stl(head, size);
}

/// The element counts an OFF or PLY header promises, and binary STL's triangle count, checked
/// against the file's size before the reader allocates for them: a header claiming billions of
/// elements in a small file is refused, not followed into the allocator. Every vertex takes at
/// least 3 bytes and every face at least 1 in any of these encodings (50 bytes per binary STL
/// triangle). A binary STL's triangles are also scanned for a nan or inf corner, which its
/// reader drops without a word. \throw InvalidInput a count the file cannot hold, or such a
/// corner.
void check_header_counts(const std::filesystem::path& path, const std::string& ext) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return;
  const std::string name = path.string();
  auto refuse = [&](const std::string& what, unsigned long long count) {
    throw InvalidInput("mesh header promises " + std::to_string(count) + " " + what +
                       " but the file has only " + std::to_string(size) + " bytes: " + name);
  };
  std::ifstream in(path, std::ios::binary);
  if (ext == ".stl") {
    char head[84];
    if (!in.read(head, 84)) return;
    if (!binary_stl(head, size)) return;  // ASCII: no count
    const std::uint32_t n = stl_count(head);
    if (84ULL + 50ULL * n > size) refuse("triangles", n);
    // A triangle with a nan or inf corner is dropped by the reader without a word (a closed
    // tetrahedron came out open, and was cut so): named here instead.
    std::vector<char> block(50 * 4096);
    for (std::uint32_t first = 0; first < n;) {
      const std::uint32_t count = std::min<std::uint32_t>(4096, n - first);
      if (!in.read(block.data(), 50LL * count)) return;
      for (std::uint32_t t = 0; t < count; ++t)
        for (int k = 0; k < 9; ++k) {  // the corners, after the normal's three floats
          float x = 0;
          std::memcpy(&x, block.data() + 50 * t + 12 + 4 * k, 4);
          if (!std::isfinite(x))
            throw InvalidInput("binary STL triangle " + std::to_string(first + t + 1) +
                               " has a non-finite coordinate (nan or inf): " + name);
        }
      first += count;
    }
    return;
  }
  auto check = [&](const std::string& element, unsigned long long n) {
    if (element == "vertex" || element == "vertices") {
      if (n > size / 3) refuse("vertices", n);
    } else if (n > size) {
      refuse(element + " elements", n);
    }
  };
  if (ext == ".off") {
    std::string word;
    if (!(in >> word) || word.find("OFF") == std::string::npos) return;
    if (word.find('4') != std::string::npos || word.find('n') != std::string::npos) return;
    std::string token;
    std::vector<unsigned long long> counts;
    while (counts.size() < 2 && in >> token) {
      if (token[0] == '#') {
        std::getline(in, token);
        continue;
      }
      if (token == "BINARY") continue;
      const char* text = token.c_str();
      char* end = nullptr;
      if (token[0] == '-') throw InvalidInput("OFF header has a negative count: " + name);
      counts.push_back(std::strtoull(text, &end, 10));
      if (*end != '\0') return;  // not a count: the reader will say so
    }
    if (counts.size() == 2) {
      check("vertex", counts[0]);
      check("face", counts[1]);
    }
    return;
  }
  if (ext == ".ply") {
    std::string line;
    for (int lines = 0; lines < 1000 && std::getline(in, line); ++lines) {
      if (line.rfind("end_header", 0) == 0) break;
      std::istringstream words(line);
      std::string keyword, element, count;
      if (!(words >> keyword >> element >> count) || keyword != "element") continue;
      if (count[0] == '-') throw InvalidInput("PLY header has a negative count: " + name);
      char* end = nullptr;
      const unsigned long long n = std::strtoull(count.c_str(), &end, 10);
      if (*end == '\0') check(element, n);
    }
  }
}

/// An ASCII mesh with a number that is not one: "nan" or "inf", a word ("abc"), or one past a
/// 32-bit float's range (1e300: OpenMesh's readers take floats). The readers stop there or drop
/// the line and report something else (no faces, an out-of-range vertex index, a face of zero
/// area, a vertex silently at 0), so the line is named here instead. \throw InvalidInput such a
/// number.
void check_ascii_numbers(const std::filesystem::path& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line)) return;
  const bool ascii = ext == ".obj" || (ext == ".stl" && !binary_stl(path)) ||
                     (ext == ".off" && line.find("BINARY") == std::string::npos) || ext == ".ply";
  if (!ascii) return;
  bool ply_ascii = false, in_body = ext != ".ply", off_header_seen = false;
  for (long long number = 1;; ++number) {
    std::istringstream words(line);
    std::string first;
    words >> first;
    if (ext == ".ply" && first == "format") ply_ascii = line.find("ascii") != std::string::npos;
    if (ext == ".ply" && first == "end_header") {
      if (!ply_ascii) return;
      in_body = true;
    }
    // Only numbers: OBJ vertex lines, STL vertex and normal lines, OFF and PLY bodies.
    const bool numbers = ext == ".obj"   ? first == "v" || first == "vn" || first == "vt"
                         : ext == ".stl" ? first == "vertex" || first == "facet"
                         : ext == ".off" ? !first.empty() && first[0] != '#'
                                         : in_body && first != "end_header";
    if (ext == ".obj" && first == "f") {  // the reader would drop a repeated corner silently
      std::vector<std::string> corners;
      for (std::string word; words >> word;) corners.push_back(word.substr(0, word.find('/')));
      // A corner without a vertex index ("f /160") trips an assertion inside OpenMesh's reader.
      for (const std::string& c : corners) {
        char* end = nullptr;
        const long index = std::strtol(c.c_str(), &end, 10);
        if (c.empty() || *end != '\0' || index == 0)
          throw InvalidInput("mesh line " + std::to_string(number) + ": face corner '" + c +
                             "' is not a vertex index: " + path.string());
      }
      if (corners.size() < 3)
        throw InvalidInput("mesh line " + std::to_string(number) + ": a face has " +
                           std::to_string(corners.size()) + " corners: " + path.string());
      for (std::size_t i = 0; i < corners.size(); ++i)
        for (std::size_t j = i + 1; j < corners.size(); ++j)
          if (corners[i] == corners[j])
            throw InvalidInput("mesh line " + std::to_string(number) + ": a face repeats vertex " +
                               corners[i] + ": " + path.string());
    }
    if (ext != ".obj" && ext != ".stl" && numbers) words.seekg(0);
    // Every word a number, up to a comment; but OFF's header keyword (first line: OFF, COFF,
    // NOFF, ...) and STL's "facet normal".
    for (std::string word; numbers && words >> word;) {
      if (word[0] == '#') break;
      if (ext == ".stl" && first == "facet" && word == "normal") continue;
      if (ext == ".off" && !off_header_seen && word.find("OFF") != std::string::npos) continue;
      std::string lower;
      for (char c : word) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      const std::size_t at = lower.find_first_not_of("+-");
      if (at == std::string::npos) continue;
      const std::string bare = lower.substr(at);
      if (bare == "nan" || bare.rfind("nan(", 0) == 0 || bare == "inf" || bare == "infinity")
        throw InvalidInput("mesh line " + std::to_string(number) + " has a non-finite number '" +
                           word + "': " + path.string());
      // Decimal only: strtod takes hexadecimal ("0x10"), the readers do not.
      char* end = nullptr;
      const double value = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0' ||
          word.find_first_not_of("0123456789+-.eE") != std::string::npos)
        throw InvalidInput("mesh line " + std::to_string(number) + ": '" + word +
                           "' is not a number: " + path.string());
      if (std::abs(value) > std::numeric_limits<float>::max())
        throw InvalidInput("mesh line " + std::to_string(number) + ": " + word +
                           " is out of range (the mesh readers read 32-bit floats, at most "
                           "3.4e38): " +
                           path.string());
    }
    if (ext == ".off" && numbers) off_header_seen = true;
    if (!std::getline(in, line)) return;
  }
}

/// An ASCII OFF file laid out as its header says: the vertex lines, then face lines that each
/// start with a whole corner count n >= 3 followed by n indices (a colour may follow). OpenMesh's
/// reader reads tokens across lines and can loop for minutes on a face count that is not one
/// (found by the fuzzer). Returns whether a face has a colour after its corners (OpenMesh's
/// reader took a face's colour of whole numbers, "255 0 0", for corners of the faces after it:
/// a coloured cube was refused for 4 faces that repeat a vertex); with \p plain, writes the
/// file there without those colours. \throw InvalidInput the line that does not fit.
bool check_off_layout(const std::filesystem::path& path, std::ostringstream* plain = nullptr) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  long long number = 0;
  auto next = [&](std::vector<std::string>& tokens) {  // the next line with content
    while (std::getline(in, line)) {
      ++number;
      const auto hash = line.find('#');
      std::istringstream words(line.substr(0, hash));
      tokens.clear();
      for (std::string w; words >> w;) tokens.push_back(w);
      if (!tokens.empty()) return true;
    }
    return false;
  };
  std::vector<std::string> t;
  if (!next(t) || t[0].find("OFF") == std::string::npos) return false;
  if (t[0] != "OFF" || line.find("BINARY") != std::string::npos) return false;  // variants
  t.erase(t.begin());
  if (t.empty() && !next(t)) return false;
  if (t.size() < 2) return false;
  bool coloured = false;
  const auto put = [&](const std::vector<std::string>& words, std::size_t count) {
    if (!plain) return;
    for (std::size_t k = 0; k < count && k < words.size(); ++k)
      *plain << (k ? " " : "") << words[k];
    *plain << "\n";
  };
  if (plain) *plain << "OFF\n";
  put(t, t.size());
  auto whole = [](const std::string& w, long long& out) {
    char* end = nullptr;
    out = std::strtoll(w.c_str(), &end, 10);
    return !w.empty() && *end == '\0';
  };
  long long nv = 0, nf = 0;
  if (!whole(t[0], nv) || !whole(t[1], nf)) return false;
  const std::string name = path.string();
  for (long long v = 0; v < nv; ++v) {
    if (!next(t) || t.size() < 3)
      throw InvalidInput("OFF line " + std::to_string(number) + ": vertex " + std::to_string(v) +
                         " needs three coordinates: " + name);
    put(t, t.size());
  }
  for (long long f = 0; f < nf; ++f) {
    long long n = 0;
    if (!next(t))
      throw InvalidInput("OFF file ends after " + std::to_string(f) + " of " + std::to_string(nf) +
                         " faces: " + name);
    if (!whole(t[0], n) || n < 3 || n > 1000000)
      throw InvalidInput(
          "OFF line " + std::to_string(number) + ": face " + std::to_string(f) +
          " does not start with a corner count n >= 3 followed by n indices: " + name);
    // A face may wrap over several lines: its n indices, whole numbers, then the next face.
    long long have = static_cast<long long>(t.size()) - 1;
    std::vector<std::string> face = plain ? t : std::vector<std::string>{};  // its words
    for (long long k = 1; k < static_cast<long long>(t.size()) && k <= n; ++k) {
      long long index = 0;
      if (!whole(t[k], index))
        throw InvalidInput("OFF line " + std::to_string(number) + ": face " + std::to_string(f) +
                           " has a corner '" + t[k] + "' that is not a vertex index: " + name);
    }
    while (have < n) {
      std::vector<std::string> more;
      if (!next(more))
        throw InvalidInput("OFF file ends inside face " + std::to_string(f) + ": " + name);
      for (const std::string& w : more) {
        long long index = 0;
        if (have < n && !whole(w, index))
          throw InvalidInput("OFF line " + std::to_string(number) + ": face " + std::to_string(f) +
                             " has a corner '" + w + "' that is not a vertex index: " + name);
        ++have;
        if (plain) face.push_back(w);
      }
    }
    coloured = coloured || have > n;  // words after its n corners: a colour
    put(face, static_cast<std::size_t>(n + 1));
  }
  return coloured;
}

int count_occurrences(const std::string& text, const std::string& needle) {
  int n = 0;
  for (auto pos = text.find(needle); pos != std::string::npos; pos = text.find(needle, pos + 1))
    ++n;
  return n;
}

/// \p mesh as read, with the faces OpenMesh could not join to their neighbours (it gives them
/// copies of their corners) joined: the copies welded to the first vertex at the same point,
/// the faces turned round to agree (orient_consistently), and added piece by piece in an order
/// where each face meets one added before; a face repeating another's corners is dropped.
/// \p count_welds: the vertices welded are the file's own (no copies made by the reader) and
/// are counted in \p repairs. \throw InvalidInput where a vertex still cannot take its faces
/// (they meet only at that corner) or orient_consistently refuses.
PolyMesh reoriented(const PolyMesh& mesh, const std::string& name, MeshRepairs* repairs,
                    bool count_welds) {
  struct Key {
    double x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      const std::hash<double> h;
      return h(k.x) ^ (h(k.y) * 31) ^ (h(k.z) * 1000003);
    }
  };
  std::unordered_map<Key, int, Hash> first;
  std::vector<int> kept(mesh.n_vertices(), -1);  // vertex -> its index in the mesh rebuilt
  std::vector<Vec3> points;
  PolyMesh vertices_only;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    const auto [it, fresh] =
        first.try_emplace(Key{p[0], p[1], p[2]}, static_cast<int>(points.size()));
    if (fresh) {
      points.push_back(to_eigen(p));
      vertices_only.add_vertex(p);
    }
    kept[v.idx()] = it->second;
  }
  std::vector<std::vector<int>> faces;
  faces.reserve(mesh.n_faces());
  std::set<std::vector<int>> seen;  // each face's corners, sorted
  int duplicates = 0;
  for (auto f : mesh.faces()) {
    std::vector<int> corners;
    for (auto v : mesh.fv_range(f)) corners.push_back(kept[v.idx()]);
    std::vector<int> sorted = corners;
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(std::move(sorted)).second) {
      ++duplicates;
      continue;
    }
    faces.push_back(std::move(corners));
  }
  const OrientedFaces oriented = orient_consistently(points, std::move(faces), name);
  // The faces in the file's order first (the mesh then is the one the file would have given
  // had its faces agreed), else piece by piece.
  const std::vector<int> in_file = [&] {
    std::vector<int> all(oriented.faces.size());
    std::iota(all.begin(), all.end(), 0);
    return all;
  }();
  std::size_t refused = 0;
  PolyMesh out;
  for (const std::vector<int>* order : std::array{&in_file, &oriented.order}) {
    out = vertices_only;
    refused = 0;
    OpenMeshLogCapture capture;
    std::vector<PolyMesh::VertexHandle> corners;
    for (int f : *order) {
      corners.clear();
      for (int v : oriented.faces[f]) corners.push_back(out.vertex_handle(v));
      if (!out.add_face(corners).is_valid()) ++refused;
    }
    if (refused == 0) break;
  }
  if (refused > 0)
    throw InvalidInput("mesh is not manifold (" + std::to_string(refused) +
                       " face(s) meet others only at a corner, a non-manifold vertex): " + name);
  if (repairs) {
    repairs->faces_turned = oriented.turned;
    repairs->duplicate_faces = duplicates;
    repairs->vertices_welded =
        count_welds ? static_cast<int>(mesh.n_vertices() - vertices_only.n_vertices()) : 0;
  }
  return out;
}

/// True where two border vertices of \p mesh lie at exactly the same point: faces that meet
/// there were not joined (an OBJ triangle soup, vertices split at texture seams).
bool has_open_seams(const PolyMesh& mesh) {
  std::set<std::array<double, 3>> at;
  for (auto v : mesh.vertices()) {
    if (!mesh.is_boundary(v) || mesh.is_isolated(v)) continue;
    const auto& p = mesh.point(v);
    if (!at.insert({p[0], p[1], p[2]}).second) return true;
  }
  return false;
}

}  // namespace

PolyMesh read_mesh(const std::filesystem::path& path, MeshRepairs* repairs) {
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError("mesh file not found: " + name);
  if (std::filesystem::is_directory(path, ec)) throw IoError("mesh path is a directory: " + name);
  if (!std::filesystem::is_regular_file(path, ec))
    throw IoError("mesh path is not a regular file (a FIFO, device or socket): " + name);
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw IoError("mesh file cannot be opened: " + name);
  }
  const std::string ext = path.extension().string();
  std::string lower;
  for (char c : ext) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower != ".obj" && lower != ".off" && lower != ".ply" && lower != ".stl")
    throw IoError("unsupported mesh format '" + ext + "' (use .obj, .off, .ply or .stl): " + name);

  check_header_counts(path, lower);
  check_ascii_numbers(path, lower);
  // A coloured OFF is read again, once, without its faces' colours.
  std::optional<std::ostringstream> plain_off;
  if (lower == ".off" && check_off_layout(path)) check_off_layout(path, &plain_off.emplace());

  PolyMesh mesh;
  std::string log;
  bool ok = false;
  {
    OpenMeshLogCapture capture;
    OpenMesh::IO::Options opt;
    if (plain_off) {
      std::istringstream text(plain_off->str());
      ok = OpenMesh::IO::read_mesh(mesh, text, ".off", opt);
    } else {
      ok = OpenMesh::IO::read_mesh(mesh, name, opt);
    }
    log = capture.text();
  }
  if (!ok) {
    std::string reason = log.substr(0, log.find('\n'));
    throw IoError("cannot read mesh " + name + (reason.empty() ? "" : ": " + reason));
  }
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InvalidInput("mesh vertex " + std::to_string(v.idx()) +
                         " has a non-finite coordinate (nan or inf): " + name);
  }

  const int repeated = count_occurrences(log, "equal vertices");
  const int invalid = count_occurrences(log, "invalid vertex index");
  if (repeated > 0)
    throw InvalidInput("mesh has " + std::to_string(repeated) +
                       " degenerate face(s) that repeat a vertex: " + name);
  if (invalid > 0)
    throw InvalidInput("mesh has " + std::to_string(invalid) +
                       " face(s) with an out-of-range vertex index: " + name);
  if (mesh.n_faces() == 0) throw InvalidInput("mesh has no faces: " + name);
  if (repairs) *repairs = MeshRepairs{};
  for (auto f : mesh.faces())
    if (mesh.status(f).fixed_nonmanifold()) return reoriented(mesh, name, repairs, false);
  // Faces meeting at vertices of the same point that the file did not join: welded where that
  // gives a mesh (a soup of a cube was read as 12 loose triangles and cut as 12 parts with no
  // joint); where it gives none (two borders touching at a point), read as it stands.
  if (has_open_seams(mesh)) {
    try {
      PolyMesh welded = reoriented(mesh, name, repairs, true);
      bool manifold = true;  // no vertex where faces meet only at their corners
      for (auto v : welded.vertices()) manifold = manifold && welded.is_manifold(v);
      if (manifold) return welded;
    } catch (const InvalidInput&) {
    }
    if (repairs) *repairs = MeshRepairs{};
  }
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
