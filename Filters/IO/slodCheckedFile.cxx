// SPDX-License-Identifier: BSD-3-Clause
#include "slodCheckedFile.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>

namespace slod
{
namespace
{
constexpr size_t BufferSize = 1 << 16;
constexpr size_t LongestNumber = 64; // room for any number to_chars writes
} // namespace

CheckedFileWriter::CheckedFileWriter()
  : Buffer(BufferSize)
{
}

CheckedFileWriter::~CheckedFileWriter()
{
  if (this->File)
  {
    std::fclose(this->File);
  }
}

std::string CheckedFileWriter::Open(const std::string& path)
{
  this->File = std::fopen(path.c_str(), "wb");
  return this->File ? std::string() : std::string("cannot open file for writing (") + std::strerror(errno) + ")";
}

void CheckedFileWriter::Drain()
{
  if (this->Used > 0 && !this->Failed && std::fwrite(this->Buffer.data(), 1, this->Used, this->File) != this->Used)
  {
    this->Failed = true;
    this->FailureErrno = errno;
  }
  this->Used = 0;
}

void CheckedFileWriter::WriteBytes(const void* data, size_t size)
{
  const char* bytes = static_cast<const char*>(data);
  while (size > 0)
  {
    if (this->Used == this->Buffer.size())
    {
      this->Drain();
    }
    const size_t chunk = std::min(size, this->Buffer.size() - this->Used);
    std::memcpy(this->Buffer.data() + this->Used, bytes, chunk);
    this->Used += chunk;
    bytes += chunk;
    size -= chunk;
  }
}

void CheckedFileWriter::WriteChar(char c)
{
  this->WriteBytes(&c, 1);
}

void CheckedFileWriter::WriteReal(double value)
{
  char text[LongestNumber];
  this->WriteBytes(text, static_cast<size_t>(std::to_chars(text, text + sizeof(text), value).ptr - text));
}

void CheckedFileWriter::WriteReal(float value)
{
  char text[LongestNumber];
  this->WriteBytes(text, static_cast<size_t>(std::to_chars(text, text + sizeof(text), value).ptr - text));
}

void CheckedFileWriter::WriteInteger(long long value)
{
  char text[LongestNumber];
  this->WriteBytes(text, static_cast<size_t>(std::to_chars(text, text + sizeof(text), value).ptr - text));
}

std::string CheckedFileWriter::Close()
{
  if (!this->File)
  {
    return "file not open";
  }
  this->Drain();
  if (!this->Failed && std::fflush(this->File) != 0)
  {
    this->Failed = true;
    this->FailureErrno = errno;
  }
  const bool closed = std::fclose(this->File) == 0;
  const int closeErrno = errno;
  this->File = nullptr;
  if (this->Failed || !closed)
  {
    return std::string("write failed (") + std::strerror(this->Failed ? this->FailureErrno : closeErrno) + ")";
  }
  return std::string();
}

void RemovePartialFile(const std::string& path)
{
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec))
  {
    std::filesystem::remove(path, ec);
  }
}

std::string WriteWholeFile(const std::string& path, const std::string& bytes)
{
  CheckedFileWriter file;
  std::string problem = file.Open(path);
  if (!problem.empty())
  {
    return problem;
  }
  file.WriteBytes(bytes.data(), bytes.size());
  problem = file.Close();
  if (!problem.empty())
  {
    RemovePartialFile(path);
  }
  return problem;
}
} // namespace slod
