// SPDX-License-Identifier: BSD-3-Clause
// Simplify a mesh by quadric-error triangle collapses, keep the progressive mesh, and rebuild an
// intermediate level from it.
//
//   QuadricTriangleCollapse input.(off|vtp) output.vtp [reduction=0.9]
#include "vtkOFFMeshReader.h"
#include "vtkProgressiveMeshReconstruction.h"
#include "vtkQuadricTriangleCollapse.h"

#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkTable.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  if (argc < 3)
  {
    std::cerr << "usage: " << argv[0] << " input.(off|vtp) output.vtp [reduction=0.9]\n";
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

  vtkNew<vtkQuadricTriangleCollapse> simplify;
  simplify->SetInputConnection(reader->GetOutputPort());
  simplify->SetTargetReduction(argc > 3 ? std::atof(argv[3]) : 0.9);
  simplify->GenerateProgressiveMeshOn(); // also record every collapse (output port 1)
  simplify->Update();
  vtkPolyData* coarse = simplify->GetOutput();
  if (coarse->GetNumberOfPolys() == 0)
  {
    std::cerr << "nothing to simplify in " << input << "\n";
    return 1;
  }
  std::cout << "simplified to " << coarse->GetNumberOfPolys() << " triangles in " << simplify->GetNumberOfCollapses()
            << " collapses, reduction " << simplify->GetActualReduction() << ", largest error "
            << simplify->GetMaximumSimplificationError() << "\n";

  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(coarse);
  writer->SetFileName(argv[2]);
  writer->Write();

  // Any level between the coarse mesh and the input, by vertex splits.
  vtkNew<vtkProgressiveMeshReconstruction> levels;
  levels->SetCoarseMeshConnection(simplify->GetOutputPort(0));
  levels->SetRecordsConnection(simplify->GetOutputPort(1));
  levels->SetTargetNumberOfTriangles(2 * coarse->GetNumberOfPolys());
  levels->Update();
  std::cout << "level with " << levels->GetOutput()->GetNumberOfPolys() << " triangles after "
            << levels->GetAppliedVertexSplits() << " of " << simplify->GetCollapseRecords()->GetNumberOfRows()
            << " vertex splits\n";
  return 0;
}
