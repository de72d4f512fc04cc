// SPDX-License-Identifier: BSD-3-Clause
// Checks of mesh files made on their bytes before a VTK reader sees them: VTK's STL reader reads a
// binary file whose triangle count disagrees with its size without a word. (OFF, PLY and OBJ are
// read by the project's own readers, which check everything themselves.)
#ifndef surfacelodMeshFileChecks_h
#define surfacelodMeshFileChecks_h

#include <string>

namespace slodcli
{
struct FileCheck
{
  std::string Problem; // "" when the file can be handed to the reader
  std::string Warning; // something the reader will drop silently ("" when none)
};

// STL: a binary file's size against the announced triangle count (short: problem, VTK's reader
// would allocate for the count; longer by whole facets: warning, it reads every facet up to the end
// of the file). `binary` must be VTK's own verdict (IsBinarySTL), not a guess from "solid": a file
// that starts with "solid" but holds binary bytes is read as binary.
FileCheck CheckSTL(const std::string& bytes, bool binary);
// The same from the file's first 84 bytes (or all of a shorter file) and its size: the tool need
// not read a large file whole before VTK's reader reads it again.
FileCheck CheckSTL(const std::string& head, unsigned long long fileSize, bool binary);
// The same for the file at path ("cannot read file (...)" when it cannot).
FileCheck CheckSTLFile(const std::string& path);

// vtkSTLReader's choice between its binary and ASCII parsers for the file at path.
bool IsBinarySTL(const std::string& path);
} // namespace slodcli

#endif
