// SPDX-License-Identifier: BSD-3-Clause
// A buffered output file whose every write, flush and close is checked: the mesh writers of
// Filters/IO report a full disk or a vanished directory instead of leaving a short file silently.
#ifndef slodCheckedFile_h
#define slodCheckedFile_h

#include <cstdio>
#include <string>
#include <vector>

namespace slod
{
class CheckedFileWriter
{
public:
  CheckedFileWriter();
  ~CheckedFileWriter();
  CheckedFileWriter(const CheckedFileWriter&) = delete;
  CheckedFileWriter& operator=(const CheckedFileWriter&) = delete;

  // "" when the file is open for writing, else the problem.
  std::string Open(const std::string& path);

  void WriteBytes(const void* data, size_t size);
  void WriteText(const std::string& text) { this->WriteBytes(text.data(), text.size()); }
  void WriteChar(char c);
  // Shortest decimal forms that read back to the same value (float: as a float).
  void WriteReal(double value);
  void WriteReal(float value);
  void WriteInteger(long long value);

  // Flushes and closes; "" on success, else the problem ("write failed (No space left on device)").
  std::string Close();

private:
  void Drain();

  FILE* File = nullptr;
  std::vector<char> Buffer;
  size_t Used = 0;
  bool Failed = false;
  int FailureErrno = 0;
};

// Removes what a failed write left at path when it is a regular file (a device or a symbolic link
// to /dev/full stays): no partial file behind a reported failure.
void RemovePartialFile(const std::string& path);

// Writes bytes made in memory to path through a CheckedFileWriter, a partial file removed on
// failure; "" on success, else the problem.
std::string WriteWholeFile(const std::string& path, const std::string& bytes);
} // namespace slod

#endif
