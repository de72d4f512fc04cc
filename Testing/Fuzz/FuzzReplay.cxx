// SPDX-License-Identifier: BSD-3-Clause
// Runs the fuzz target's entry point on files (or on every file of directories) without libFuzzer:
// the seed corpus and the inputs the fuzzer once found are replayed by ctest in every build, with
// any compiler. Exit 0 when every input ran (a finding aborts the process).
#include "FuzzMeshInput.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

int main(int argc, char* argv[])
{
  std::vector<std::filesystem::path> inputs;
  for (int i = 1; i < argc; ++i)
  {
    const std::filesystem::path path(argv[i]);
    if (std::filesystem::is_directory(path))
    {
      for (const auto& entry : std::filesystem::directory_iterator(path))
      {
        if (entry.is_regular_file())
        {
          inputs.push_back(entry.path());
        }
      }
    }
    else if (std::filesystem::is_regular_file(path))
    {
      inputs.push_back(path);
    }
    else
    {
      std::cerr << "FuzzReplay: no such input: " << path << "\n";
      return 1;
    }
  }
  if (inputs.empty())
  {
    std::cerr << "FuzzReplay: no inputs\n";
    return 1;
  }
  std::sort(inputs.begin(), inputs.end());
  for (const auto& path : inputs)
  {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::cout << "replaying " << path.filename().string() << " (" << bytes.size() << " bytes)" << std::endl;
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  }
  std::cout << inputs.size() << " inputs replayed" << std::endl;
  return 0;
}
