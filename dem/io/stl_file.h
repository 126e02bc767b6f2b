// STL input: ASCII and binary STL files read into a finalized TriangleMesh (docs/meshes.md).
#pragma once

#include <string>

#include "dem/engine/triangle_mesh.h"

namespace trackbed::dem {

// Reads an ASCII or binary STL file and returns the finalized mesh. Binary is recognised by its
// size, 84 + 50 n bytes for the n triangles its header declares (binary headers may begin with
// "solid" too); otherwise a text file beginning with "solid" is ASCII. Every ASCII
// `solid NAME ... endsolid` block becomes a part named NAME (blocks with the same name share a
// part; a nameless block is named after the file stem); a binary file is one part named after the
// file stem. Facet normals in the file are ignored: the vertex order defines the orientation.
// Throws InputError ("FILE:LINE: message" for ASCII) for a missing file, a truncated binary file,
// malformed ASCII, non-finite coordinates, no triangles, or a degenerate triangle.
TriangleMesh read_stl(const std::string& path);

}  // namespace trackbed::dem
