// SPDX-License-Identifier: BSD-3-Clause
// Checks of mesh files made on their bytes before a VTK reader sees them: VTK's PLY reader crashes
// on out-of-range face indices and on truncated or oversized data, and its STL reader reads a
// binary file whose triangle count disagrees with its size without a word.
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

// Whole PLY file: header syntax, element counts the file can hold, every element and list present,
// list lengths, and every face / strip index within the vertex count; data after the last element
// is a warning.
FileCheck CheckPLY(const std::string& bytes);

// STL: a binary file's size against the announced triangle count (short: problem, VTK's reader
// would allocate for the count; longer by whole facets: warning, it reads every facet up to the end
// of the file). `binary` must be VTK's own verdict (IsBinarySTL), not a guess from "solid": a file
// that starts with "solid" but holds binary bytes is read as binary.
FileCheck CheckSTL(const std::string& bytes, bool binary);

// vtkSTLReader's choice between its binary and ASCII parsers for the file at path.
bool IsBinarySTL(const std::string& path);

// OBJ vertex lines: VTK's OBJ reader turns a coordinate it cannot parse ("nan", "1,5") into a
// number without a word, so every "v" line must hold three to seven finite numbers.
FileCheck CheckOBJ(const std::string& bytes);

// Reads a whole file into memory; false (and errno set) when it cannot be read.
bool ReadFileBytes(const std::string& path, std::string& bytes);
} // namespace slodcli

#endif
