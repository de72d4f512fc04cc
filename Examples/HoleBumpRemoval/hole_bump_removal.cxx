// SPDX-License-Identifier: BSD-3-Clause
// Topology simplification (Ho 1999, chapter 5): small holes, bumps, cavities and cracks go, the
// outer profile stays.
//
//   hole_bump_removal [input.off|plate|mixed] output_prefix [alpha (relative, default 0.05)]
//
// "plate" and "mixed" are vtkBlockModelSource models (a plate with a grid of holes; bumps, cavities
// and a hole on a box). Writes <prefix>.vtp (the result, cell data PatchId / FilledPatch) and
// <prefix>_loops.vtp (the sharp loops, cell data FeatureKind / Removed), and prints the counts
// for both completions: the patches triangulated from their exact boundaries, and the input's
// triangles kept apart from the removed features.
#include "vtkBlockModelSource.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkOFFMeshReader.h"

#include "vtkAlgorithmOutput.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkXMLPolyDataWriter.h"

#include <cstdlib>
#include <iostream>
#include <string>

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
    std::cerr << "usage: " << argv[0] << " input.off|plate|mixed output_prefix [alpha]\n";
    return 1;
  }
  const std::string input = argv[1], prefix = argv[2];
  const double alpha = argc > 3 ? std::atof(argv[3]) : 0.05;

  vtkSmartPointer<vtkPolyDataAlgorithm> source;
  if (input == "plate" || input == "mixed")
  {
    auto block = vtkSmartPointer<vtkBlockModelSource>::New();
    block->SetModel(input == "plate" ? vtkBlockModelSource::PLATE_WITH_HOLES : vtkBlockModelSource::MIXED);
    source = block;
  }
  else
  {
    auto reader = vtkSmartPointer<vtkOFFMeshReader>::New();
    reader->SetFileName(input.c_str());
    source = reader;
  }
  source->Update();
  const vtkIdType inputTriangles = source->GetOutput()->GetNumberOfPolys();

  vtkNew<vtkHoleBumpRemoval> removal;
  removal->SetInputConnection(source->GetOutputPort());
  removal->SetFeatureSize(alpha); // relative to the bounding-box diagonal
  removal->Update();
  std::cout << "input: " << inputTriangles << " triangles, genus " << removal->GetInputGenus() << "\n";
  std::cout << "holes " << removal->GetNumberOfHolesRemoved() << "/" << removal->GetNumberOfHolesDetected()
            << ", bumps " << removal->GetNumberOfBumpsRemoved() << "/" << removal->GetNumberOfBumpsDetected()
            << ", cavities " << removal->GetNumberOfCavitiesRemoved() << "/" << removal->GetNumberOfCavitiesDetected()
            << ", cracks " << removal->GetNumberOfCracksFilled() << "/" << removal->GetNumberOfCracksDetected()
            << " removed/detected\n";
  std::cout << "triangulated patches: " << removal->GetOutput()->GetNumberOfPolys() << " triangles, genus "
            << removal->GetOutputGenus() << "\n";
  Write(removal->GetOutput(0), prefix + ".vtp");
  Write(removal->GetOutput(1), prefix + "_loops.vtp");

  removal->SetCompletionToKeepTriangles();
  removal->Update();
  std::cout << "input triangles kept: " << removal->GetOutput()->GetNumberOfPolys() << " triangles, genus "
            << removal->GetOutputGenus() << "\n";
  Write(removal->GetOutput(0), prefix + "_kept.vtp");
  return 0;
}
