// SPDX-License-Identifier: BSD-3-Clause
#include "MeshFileChecks.h"

#include <vtksys/SystemTools.hxx>

#include <string>

namespace slodcli
{
FileCheck CheckSTL(const std::string& bytes, bool binary)
{
  FileCheck result;
  if (!binary)
  {
    return result; // VTK's ASCII parser reports its own errors
  }
  if (bytes.size() < 84)
  {
    result.Problem = "not an STL file (too short for a binary STL, not text)";
    return result;
  }
  const unsigned char* count = reinterpret_cast<const unsigned char*>(bytes.data()) + 80;
  const unsigned long long announced = count[0] | (count[1] << 8) | (count[2] << 16) |
    (static_cast<unsigned long long>(count[3]) << 24);
  const unsigned long long expected = 84 + 50 * announced;
  const unsigned long long size = bytes.size();
  // vtkSTLReader allocates for the announced count whatever the file holds.
  if (size < expected)
  {
    result.Problem = "truncated binary STL: the header announces " + std::to_string(announced) + " triangles (" +
      std::to_string(expected) + " bytes), the file has " + std::to_string(size) + " bytes";
  }
  else if (size >= expected + 50)
  {
    result.Warning = "binary STL holds " + std::to_string((size - expected) / 50) +
      " more triangles than the header announces (" + std::to_string(announced) + "); all are read";
  }
  return result;
}

bool IsBinarySTL(const std::string& path)
{
  // The test vtkSTLReader::GetSTLFileType makes (unknown: it attempts binary).
  return vtksys::SystemTools::DetectFileType(path.c_str()) != vtksys::SystemTools::FileTypeText;
}
} // namespace slodcli
