// SPDX-License-Identifier: BSD-3-Clause
// Re-tile a surface with a given number of evenly spread vertices (Turk 1992) and write it.
//
//   Retile input.(off|vtp) output.vtp [points=2000] [curvature-weight=0]
#include "vtkOFFMeshReader.h"
#include "vtkRetile.h"

#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  if (argc < 3)
  {
    std::cerr << "usage: " << argv[0] << " input.(off|vtp) output.vtp [points=2000] [curvature-weight=0]\n";
    return 1;
  }
  const std::string input = argv[1];
  vtkSmartPointer<vtkAlgorithm> reader;
  if (input.size() > 4 && input.substr(input.size() - 4) == ".off")
  {
    auto off = vtkSmartPointer<vtkOFFMeshReader>::New();
    off->SetFileName(input.c_str());
    reader = off;
  }
  else
  {
    auto xml = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    xml->SetFileName(input.c_str());
    reader = xml;
  }

  vtkNew<vtkRetile> retile;
  retile->SetInputConnection(reader->GetOutputPort());
  retile->SetNumberOfPoints(argc > 3 ? std::atoi(argv[3]) : 2000); // or SetTargetNumberOfTriangles(n)
  retile->SetCurvatureWeight(argc > 4 ? std::atof(argv[4]) : 0.0); // > 0: more vertices where it curves
  retile->SetRepulsionIterations(20);
  retile->SetRandomSeed(1); // same seed, same mesh
  retile->Update();
  vtkPolyData* out = retile->GetOutput();
  if (out->GetNumberOfPolys() == 0)
  {
    std::cerr << "nothing to re-tile in " << input << "\n";
    return 1;
  }
  std::cout << "re-tiled with " << out->GetNumberOfPoints() << " vertices and " << out->GetNumberOfPolys()
            << " triangles (" << retile->GetNumberOfRetainedVertices() << " original vertices kept)\n";
  std::cout << "nearest-neighbour spacing min/mean: random " << retile->GetMinimumSpacingBefore() / retile->GetMeanSpacingBefore()
            << ", after repulsion " << retile->GetMinimumSpacingAfter() / retile->GetMeanSpacingAfter() << "\n";

  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(out);
  writer->SetFileName(argv[2]);
  writer->Write();
  return 0;
}
