// SPDX-License-Identifier: BSD-3-Clause
// The libFuzzer entry point of the mesh input fuzz target (FuzzMeshInput.cxx), shared by the
// libFuzzer build, the replay driver and the seed generator.
#ifndef SurfaceLODFuzzMeshInput_h
#define SurfaceLODFuzzMeshInput_h

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

// An input is a selector byte, then the file: selector i < SurfaceLODFuzzFormatCount is a file with
// extension SurfaceLODFuzzFormats[i]; selector SurfaceLODFuzzFormatCount is a raw vtkPolyData.
constexpr unsigned SurfaceLODFuzzFormatCount = 4;
extern const char* const SurfaceLODFuzzFormats[SurfaceLODFuzzFormatCount];

#endif
