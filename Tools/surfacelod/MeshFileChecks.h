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

// STL: binary size against the announced triangle count (short: problem; longer by whole facets:
// warning, VTK's reader reads every facet up to the end of the file); ASCII when it starts with
// "solid".
FileCheck CheckSTL(const std::string& bytes);

// OBJ vertex lines: VTK's OBJ reader turns a coordinate it cannot parse ("nan", "1,5") into a
// number without a word, so every "v" line must hold three to seven finite numbers.
FileCheck CheckOBJ(const std::string& bytes);

// Reads a whole file into memory; false (and errno set) when it cannot be read.
bool ReadFileBytes(const std::string& path, std::string& bytes);
} // namespace slodcli

#endif
