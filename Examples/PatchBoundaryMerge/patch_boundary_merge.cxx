// SPDX-License-Identifier: BSD-3-Clause
// Several levels of detail of one surface from a single patchification (SPBM, Ho 1999).
//
//   patch_boundary_merge input.off output_prefix [triangles...]
//
// Writes <prefix>_patches.vtp (the input coloured by patch), and for each triangle count
// <prefix>_<n>.vtp (the simplified mesh, cell data PatchId) and <prefix>_<n>_curves.vtp (the
// profile curves). Only the first level computes the patches; the others reuse them.
#include "vtkOFFMeshReader.h"
#include "vtkPatchBoundaryMerge.h"

#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkXMLPolyDataWriter.h"

#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

static void Write(vtkPolyData* data, const std::string& fileName)
{
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(data);
  writer->SetFileName(fileName.c_str());
  writer->Write();
}

int main(int argc, char* argv[])
{
  if (argc < 3)
  {
    std::cerr << "usage: " << argv[0] << " input.off output_prefix [triangles...]\n";
    return 1;
  }
  std::vector<vtkIdType> levels;
  for (int i = 3; i < argc; ++i)
  {
    levels.push_back(std::atol(argv[i]));
  }
  if (levels.empty())
  {
    levels = { 460, 266, 150 }; // Table 1 of the dissertation for the Fandisk
  }
  const std::string prefix = argv[2];

  vtkNew<vtkOFFMeshReader> reader;
  reader->SetFileName(argv[1]);

  vtkNew<vtkPatchBoundaryMerge> spbm;
  spbm->SetInputConnection(reader->GetOutputPort());
  spbm->GeneratePatchColoredInputOn(); // output port 2
  for (const vtkIdType triangles : levels)
  {
    spbm->SetTargetNumberOfTriangles(triangles);
    spbm->Update();
    std::cout << triangles << " requested: " << spbm->GetOutput()->GetNumberOfPolys() << " triangles, "
              << spbm->GetNumberOfMergedPatches() << " patches (patchification: " << spbm->GetNumberOfPatches()
              << (spbm->GetPatchificationReused() ? ", reused" : "") << "), epsilon " << spbm->GetUsedEpsilon()
              << ", alpha1 " << spbm->GetUsedMergeAngle() << " deg, " << spbm->GetLevelTime() << " s\n";
    Write(spbm->GetOutput(0), prefix + "_" + std::to_string(triangles) + ".vtp");
    Write(spbm->GetOutput(1), prefix + "_" + std::to_string(triangles) + "_curves.vtp");
  }
  Write(spbm->GetOutput(2), prefix + "_patches.vtp");
  return 0;
}
