// Placeholder replaced by the implementation.
#include "vtkSurfaceDeviation.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
vtkStandardNewMacro(vtkSurfaceDeviation);
vtkSurfaceDeviation::vtkSurfaceDeviation() { this->SetNumberOfInputPorts(2); }
void vtkSurfaceDeviation::PrintSelf(ostream& os, vtkIndent indent) { this->Superclass::PrintSelf(os, indent); }
int vtkSurfaceDeviation::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}
int vtkSurfaceDeviation::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) { return 1; }
