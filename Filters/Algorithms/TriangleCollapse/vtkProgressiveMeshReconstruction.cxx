// SPDX-License-Identifier: BSD-3-Clause
#include "vtkProgressiveMeshReconstruction.h"

#include "slodAttributeTransfer.h"
#include "slodCollapseRecordTable.h"
#include "slodEditableMesh.h"
#include "slodInputPreparation.h"
#include "slodTriangleCollapse.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTable.h"

#include <algorithm>

vtkStandardNewMacro(vtkProgressiveMeshReconstruction);

namespace
{
// The original mesh's input cell of each prepared triangle (empty: no cell data to carry), cached.
struct OriginalCells
{
  std::vector<slod::Index> TriangleToCell;
  const void* Data = nullptr;
  vtkMTimeType Time = 0;
};
} // namespace

struct vtkProgressiveMeshReconstruction::State
{
  slod::EditableMesh Mesh;
  slod::CollapseRecords History;
  std::vector<vtkIdType> TrianglesAtLevel; // triangle count after s splits
  vtkIdType Applied = 0;
  vtkMTimeType CoarseTime = 0, RecordsTime = 0;
  const void* CoarseData = nullptr;
  const void* RecordsData = nullptr;
  int PointType = VTK_DOUBLE;
  vtkIdType InputTriangles = 0; // of the prepared input the records refer to
  OriginalCells Original;
};

vtkProgressiveMeshReconstruction::vtkProgressiveMeshReconstruction()
{
  this->SetNumberOfInputPorts(3);
}

vtkProgressiveMeshReconstruction::~vtkProgressiveMeshReconstruction() = default;

int vtkProgressiveMeshReconstruction::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
    return 1;
  }
  if (port == 2)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return this->Superclass::FillInputPortInformation(port, info);
}

namespace
{
// The coarse level over the input's ids: the coarse points at their original vertex ids, the
// removed triangles as they were when removed (their storage is what a split revives), the live
// ones from the coarse cells. Returns an error message, or nullptr.
const char* CoarseLevel(vtkPolyData* coarse, const slod::CollapseRecords& h, vtkIdType np, vtkIdType nt,
  slod::TriangleMesh& mesh, std::vector<unsigned char>& live)
{
  vtkDataArray* vertexIds = coarse->GetPointData()->GetArray("OriginalVertexId");
  vtkDataArray* triangleIds = coarse->GetCellData()->GetArray("OriginalTriangleId");
  if (!vertexIds || !triangleIds || !coarse->GetPolys())
  {
    return "The coarse mesh lacks OriginalVertexId / OriginalTriangleId (turn GenerateProgressiveMesh on).";
  }
  mesh.Points.assign(3 * size_t(np), 0.0);
  mesh.Triangles.assign(3 * size_t(nt), 0);
  live.assign(size_t(nt), 0);
  for (vtkIdType i = 0; i < coarse->GetNumberOfPoints(); ++i)
  {
    const auto v = static_cast<vtkIdType>(vertexIds->GetComponent(i, 0));
    if (v < 0 || v >= np)
    {
      return "OriginalVertexId out of range.";
    }
    coarse->GetPoint(i, &mesh.Points[3 * size_t(v)]);
  }
  for (size_t r = 0; r < h.RemovedTriangles.size(); ++r)
  {
    std::copy_n(&h.RemovedTriangleVertices[3 * r], 3, &mesh.Triangles[3 * size_t(h.RemovedTriangles[r])]);
  }
  vtkCellArray* polys = coarse->GetPolys();
  vtkIdType cell = 0;
  vtkIdType npts;
  const vtkIdType* pts;
  for (polys->InitTraversal(); polys->GetNextCell(npts, pts); ++cell)
  {
    const auto t = static_cast<vtkIdType>(triangleIds->GetComponent(cell, 0));
    if (npts != 3 || t < 0 || t >= nt)
    {
      return "The coarse mesh is not the collapse filter's output (bad cell or OriginalTriangleId).";
    }
    for (int k = 0; k < 3; ++k)
    {
      mesh.Triangles[3 * size_t(t) + k] = static_cast<slod::Index>(vertexIds->GetComponent(pts[k], 0));
    }
    live[t] = 1;
  }
  return nullptr;
}

// The input cell of each prepared triangle of `original` into cells (cached), or nothing with a
// warning when it is not the mesh the records were made from (inputTriangles triangles).
void MapOriginalCells(vtkObject* filter, vtkPolyData* original, vtkIdType inputTriangles, OriginalCells& cells)
{
  if (cells.Data == original && cells.Time == original->GetMTime())
  {
    return;
  }
  cells.Data = original;
  cells.Time = original->GetMTime();
  slod::TriangleMesh mesh;
  std::vector<slod::Index> vertexToInput;
  slod::PrepareTriangleMesh(
    original, slod::PreparationOptions(), mesh, vertexToInput, slod::CellMapIfNeeded(original, cells.TriangleToCell));
  if (!cells.TriangleToCell.empty() && mesh.NumberOfTriangles() != inputTriangles)
  {
    vtkWarningWithObjectMacro(filter, << "The original mesh (input 2) has " << mesh.NumberOfTriangles()
                                      << " triangles, the records " << inputTriangles
                                      << ": it is not their input, its cell data is not carried.");
    cells.TriangleToCell.clear();
  }
}

// Output triangle i is the i-th live triangle of `mesh` (EditableMesh::Extract): its cell data is
// that of its own input cell, when the original mesh is given.
void StoreOriginalCellData(vtkObject* filter, vtkPolyData* coarse, vtkPolyData* original, const slod::EditableMesh& mesh,
  vtkIdType inputTriangles, OriginalCells& cells, vtkPolyData* output)
{
  if (!original)
  {
    if (coarse->GetCellData()->GetNumberOfArrays() > 1) // more than OriginalTriangleId
    {
      vtkWarningWithObjectMacro(filter, << "The coarse mesh has cell data: connect the original mesh to input 2 "
                                           "(SetOriginalMeshConnection) to carry it to every triangle.");
    }
    return;
  }
  MapOriginalCells(filter, original, inputTriangles, cells);
  std::vector<slod::Index> liveTriangles;
  for (slod::Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    if (mesh.IsTriangleAlive(t))
    {
      liveTriangles.push_back(t);
    }
  }
  slod::StoreCellData(original, cells.TriangleToCell, liveTriangles, output);
}

// The triangle count after s vertex splits, for every s.
std::vector<vtkIdType> TrianglesAtLevels(const slod::CollapseRecords& h, vtkIdType coarseTriangles)
{
  const slod::Index n = h.NumberOfCollapses();
  std::vector<vtkIdType> count(size_t(n) + 1);
  count[0] = coarseTriangles;
  for (slod::Index s = 1; s <= n; ++s)
  {
    const slod::Index k = n - s; // record undone by split s
    count[s] = count[s - 1] + h.RemovedCount(k);
  }
  return count;
}
} // namespace

int vtkProgressiveMeshReconstruction::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* coarse = vtkPolyData::GetData(inputVector[0], 0);
  vtkTable* table = vtkTable::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->OperationsLastUpdate = 0;
  if (!coarse || !table || !output)
  {
    vtkErrorMacro(<< "Needs the coarse mesh (port 0) and the collapse records (port 1).");
    return 1;
  }

  // (Re)build the state at the coarse level when an input changed.
  if (!this->Cache || this->Cache->CoarseData != coarse || this->Cache->RecordsData != table ||
    this->Cache->CoarseTime != coarse->GetMTime() || this->Cache->RecordsTime != table->GetMTime())
  {
    this->Cache.reset();
    auto state = std::make_unique<State>();
    slod::Index np = 0, nt = 0;
    if (!slod::TableToCollapseRecords(table, state->History, np, nt))
    {
      vtkErrorMacro(<< "The collapse records are malformed (see vtkQuadricTriangleCollapse, output port 1).");
      return 1;
    }
    slod::TriangleMesh mesh;
    std::vector<unsigned char> live;
    if (const char* error = CoarseLevel(coarse, state->History, np, nt, mesh, live))
    {
      vtkErrorMacro(<< error);
      return 1;
    }
    state->Mesh.Reset(mesh);
    for (slod::Index t = 0; t < nt; ++t)
    {
      if (!live[t])
      {
        state->Mesh.RemoveTriangle(t);
      }
    }
    state->TrianglesAtLevel = TrianglesAtLevels(state->History, coarse->GetNumberOfPolys());
    state->PointType = coarse->GetPoints() ? coarse->GetPoints()->GetDataType() : VTK_DOUBLE;
    state->InputTriangles = nt;
    state->CoarseData = coarse;
    state->RecordsData = table;
    state->CoarseTime = coarse->GetMTime();
    state->RecordsTime = table->GetMTime();
    this->Cache = std::move(state);
  }

  State& state = *this->Cache;
  const vtkIdType n = state.History.NumberOfCollapses();
  vtkIdType level = this->NumberOfVertexSplits < 0 ? n : std::min(this->NumberOfVertexSplits, n);
  if (this->TargetNumberOfTriangles > 0)
  {
    level = std::lower_bound(state.TrianglesAtLevel.begin(), state.TrianglesAtLevel.end(), this->TargetNumberOfTriangles) -
      state.TrianglesAtLevel.begin();
    level = std::min(level, n);
  }
  slod::CollapseRecord record;
  while (state.Applied < level) // vertex splits, newest record first
  {
    state.History.Undo(static_cast<slod::Index>(n - 1 - state.Applied), state.Mesh, record);
    ++state.Applied;
    ++this->OperationsLastUpdate;
  }
  while (state.Applied > level) // back to coarser levels: redo the collapses in order
  {
    state.History.Redo(static_cast<slod::Index>(n - state.Applied), state.Mesh, record);
    --state.Applied;
    ++this->OperationsLastUpdate;
  }
  this->AppliedVertexSplits = state.Applied;

  slod::TriangleMesh out;
  std::vector<slod::Index> newToOld;
  state.Mesh.Extract(out, &newToOld);
  slod::MeshToPolyData(out, output, state.PointType == VTK_DOUBLE ? VTK_DOUBLE : VTK_FLOAT);
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName("OriginalVertexId");
  ids->SetNumberOfTuples(static_cast<vtkIdType>(newToOld.size()));
  std::copy(newToOld.begin(), newToOld.end(), ids->GetPointer(0));
  output->GetPointData()->AddArray(ids);
  StoreOriginalCellData(this, coarse, vtkPolyData::GetData(inputVector[2], 0), state.Mesh, state.InputTriangles,
    state.Original, output);
  return 1;
}

void vtkProgressiveMeshReconstruction::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfVertexSplits: " << this->NumberOfVertexSplits << "\n";
  os << indent << "TargetNumberOfTriangles: " << this->TargetNumberOfTriangles << "\n";
  os << indent << "AppliedVertexSplits: " << this->AppliedVertexSplits << "\n";
  os << indent << "OperationsLastUpdate: " << this->OperationsLastUpdate << "\n";
}
