// SPDX-License-Identifier: BSD-3-Clause
#include "vtkBlockModelSource.h"

#include "slodBlockModel.h"
#include "slodInputPreparation.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"

vtkStandardNewMacro(vtkBlockModelSource);

vtkBlockModelSource::vtkBlockModelSource()
{
  this->SetNumberOfInputPorts(0);
}

int vtkBlockModelSource::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  const int nx = 2 * this->FeaturesX + 1, ny = 2 * this->FeaturesY + 1;
  slod::TriangleMesh mesh;
  if (this->Model == PLATE_WITH_HOLES)
  {
    mesh = slod::PlateWithHoles(this->FeaturesX, this->FeaturesY, 0.5, this->Subdivisions);
  }
  else if (this->Model == PLATE_WITH_ROUND_HOLES)
  {
    mesh = slod::PlateWithRoundHoles(this->FeaturesX, this->FeaturesY, 0.3, this->Segments - this->Segments % 4, 0.3);
  }
  else
  {
    const double feature = this->Model == CAVITIES ? 0.6 : 1.4;
    std::vector<double> heights(size_t(nx) * size_t(ny), 1.0);
    for (int j = 1; j < ny; j += 2)
    {
      for (int i = 1; i < nx; i += 2)
      {
        heights[size_t(i) + size_t(nx) * size_t(j)] = feature;
      }
    }
    if (this->Model == MIXED)
    {
      const int k = this->FeaturesX * this->FeaturesY;
      const int first = 1 + nx, middle = (nx / 2 | 1) + nx * (ny / 2 | 1), last = (nx - 2) + nx * (ny - 2);
      if (k >= 2)
      {
        heights[size_t(first)] = 0.6;
      }
      if (k >= 3)
      {
        heights[size_t(middle)] = 0.0;
      }
      if (k >= 4)
      {
        heights[size_t(last)] = 0.5;
      }
    }
    mesh = slod::BlockModel(nx, ny, heights, 1.0, this->Subdivisions);
  }
  slod::MeshToPolyData(mesh, output, VTK_DOUBLE);
  return 1;
}

void vtkBlockModelSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Model: " << this->Model << "\n";
  os << indent << "FeaturesX: " << this->FeaturesX << "\n";
  os << indent << "FeaturesY: " << this->FeaturesY << "\n";
  os << indent << "Subdivisions: " << this->Subdivisions << "\n";
  os << indent << "Segments: " << this->Segments << "\n";
}
