// SPDX-License-Identifier: BSD-3-Clause
// The inputs of `surfacelod demo` and `surfacelod bench`: generated surfaces by name
// (synthetic:N, noisy:N, mask:N, openscan:N), mesh files, CGAL demo meshes, and the named sets.
#ifndef surfacelodBenchInputs_h
#define surfacelodBenchInputs_h

#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <string>
#include <vector>

namespace slodcli
{
// The demo's smooth surface (vtkSyntheticIsosurfaceSource); seconds: generation time.
vtkSmartPointer<vtkPolyData> MakeSyntheticSurface(int resolution, double* seconds = nullptr);

// A bench input: a generated surface by name, a mesh file, or <meshDir>/<name>.off. Throws
// CliError (usage) for a malformed generator name, (data) for an unreadable file.
vtkSmartPointer<vtkPolyData> ResolveBenchInput(const std::string& name, const std::string& meshDir);

// Description of the generator names, for --help.
std::string GeneratedInputHelp();

// `--set real`: the scan-like generated surfaces at about one million triangles each.
std::vector<std::string> RealInputSet();
// `--scaling`: the noisy isosurface at about 0.25M, 1M and 4M triangles (in that order), or at
// the three resolutions given (--scaling-resolutions, for quick checks).
std::vector<std::string> ScalingInputSet(const std::vector<std::string>& resolutions = {});
std::string DefaultScalingResolutions(); // "137,273,546"
} // namespace slodcli

#endif
