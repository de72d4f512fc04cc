// SPDX-License-Identifier: BSD-3-Clause
#include "MeshFileChecks.h"

#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace slodcli
{
namespace
{
constexpr size_t BinaryHeaderSize = 84; // 80 bytes of text, the uint32 triangle count
}

FileCheck CheckSTL(const std::string& bytes, bool binary)
{
  return CheckSTL(bytes.substr(0, BinaryHeaderSize), bytes.size(), binary);
}

FileCheck CheckSTLFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open())
  {
    return { std::string("cannot read file (") + std::strerror(errno) + ")", std::string() };
  }
  std::string head(BinaryHeaderSize, '\0');
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(in ? head.size() : static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (in.bad() || ec)
  {
    return { "cannot read file (" + (ec ? ec.message() : std::string(std::strerror(errno))) + ")", std::string() };
  }
  return CheckSTL(head, size, IsBinarySTL(path));
}

FileCheck CheckSTL(const std::string& head, unsigned long long fileSize, bool binary)
{
  FileCheck result;
  if (!binary)
  {
    return result; // VTK's ASCII parser reports its own errors
  }
  if (fileSize < BinaryHeaderSize || head.size() < BinaryHeaderSize)
  {
    result.Problem = "not an STL file (too short for a binary STL, not text)";
    return result;
  }
  const unsigned char* count = reinterpret_cast<const unsigned char*>(head.data()) + 80;
  const unsigned long long announced = count[0] | (count[1] << 8) | (count[2] << 16) |
    (static_cast<unsigned long long>(count[3]) << 24);
  const unsigned long long expected = 84 + 50 * announced;
  const unsigned long long size = fileSize;
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
