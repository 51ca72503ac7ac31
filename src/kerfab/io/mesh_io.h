#pragma once
/// \file Mesh file input and output through OpenMesh (OBJ, OFF, PLY ascii/binary, STL).
#include <filesystem>

#include "kerfab/core/mesh.h"

namespace kerfab {

/// Reads a polygon mesh. Vertex indices follow the file (isolated vertices are kept, so
/// indices stay those a user sees in the file).
/// \throw IoError the file is missing, unreadable or of an unknown format.
/// \throw InvalidInput the file has no faces, a face with a repeated or invalid vertex,
///        or a non-manifold edge/vertex (reported with the count of affected faces).
PolyMesh read_mesh(const std::filesystem::path& path);

/// Writes \p mesh to \p path, format from the extension (.obj, .off, .ply, .stl).
/// \throw IoError the file could not be written.
void write_mesh(const PolyMesh& mesh, const std::filesystem::path& path);

}  // namespace kerfab
