#pragma once
/// \file Mesh file input and output through OpenMesh (OBJ, OFF, PLY ascii/binary, STL).
#include <filesystem>

#include "kerfab/core/mesh.h"

namespace kerfab {

/// What read_mesh mended in a file it read.
struct MeshRepairs {
  /// Faces whose corner order was reversed: their neighbours walk the edges they share the
  /// same way (the file's faces turn different ways), or a closed piece faced inwards with them.
  int faces_turned = 0;
  /// Vertices joined to another at exactly the same point, where the file's faces had not
  /// been joined there (a triangle soup, or vertices split at texture seams): only where such
  /// a vertex lies on a border of the mesh as read.
  int vertices_welded = 0;
  /// Faces dropped that repeat another face's corners (once welded), either way round.
  int duplicate_faces = 0;
};

/// Reads a polygon mesh. Vertex indices follow the file (isolated vertices are kept, so
/// indices stay those a user sees in the file). A file whose faces turn different ways
/// (neighbours walk a shared edge the same way) has them turned round (orient_consistently),
/// each closed piece facing out, its vertices at the same point welded into one, and says so
/// in \p repairs. So does a file whose border vertices include two at exactly the same point
/// (an OBJ triangle soup, vertices split at texture seams), where the welded mesh is one
/// (else it is read as it stands), and faces repeating another's corners are dropped.
/// \throw IoError the file is missing, unreadable or of an unknown format.
/// \throw InvalidInput the file has no faces, a face with a repeated or invalid vertex, an
///        edge on more than two faces, a vertex where faces meet only at their corners
///        (reported with the count of affected faces), or a one-sided surface.
PolyMesh read_mesh(const std::filesystem::path& path, MeshRepairs* repairs = nullptr);

/// Writes \p mesh to \p path, format from the extension (.obj, .off, .ply, .stl).
/// \throw IoError the file could not be written.
void write_mesh(const PolyMesh& mesh, const std::filesystem::path& path);

}  // namespace kerfab
