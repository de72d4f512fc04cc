// SPDX-License-Identifier: BSD-3-Clause
#include "vtkTriangleCollapseHierarchy.h"

#include "slodCollapseHierarchy.h"
#include "slodAttributeTransfer.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodPointAttributes.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <chrono>
#include <cmath>
#include <cstring>

vtkStandardNewMacro(vtkTriangleCollapseHierarchy);

struct vtkTriangleCollapseHierarchy::Internals
{
  // The cached hierarchy and what it was built from.
  bool Valid = false;
  vtkPolyData* Input = nullptr;
  vtkMTimeType InputTime = 0;
  slod::CollapseHierarchyParameters Parameters;
  int PointDataType = VTK_FLOAT;

  slod::CollapseHierarchy Hierarchy;
  slod::PointAttributes Attributes; // one row per global vertex
  std::vector<slod::Index> TriangleToCell; // input cell of each M0 triangle (empty: no cell data)
  vtkSmartPointer<vtkMultiBlockDataSet> Levels;
  slod::HierarchyMesh Scratch;
  std::vector<slod::Index> Rows;

  static bool Same(const slod::CollapseHierarchyParameters& a, const slod::CollapseHierarchyParameters& b)
  {
    return a.CurvatureWeight == b.CurvatureWeight && a.AngleWeight == b.AngleWeight &&
      a.ValenceWeight == b.ValenceWeight && a.BatchFraction == b.BatchFraction &&
      a.MaximumWeight == b.MaximumWeight && a.ValenceNormalizer == b.ValenceNormalizer &&
      a.RemoveCycles == b.RemoveCycles && a.MaximumNumberOfLevels == b.MaximumNumberOfLevels &&
      a.RelaxWhenBlocked == b.RelaxWhenBlocked && a.EdgeCollapses == b.EdgeCollapses &&
      a.PreferEdgeFactor == b.PreferEdgeFactor && a.PreventNewValenceThree == b.PreventNewValenceThree &&
      a.VertexErrorWeight == b.VertexErrorWeight &&
      a.BoundaryWeight == b.BoundaryWeight &&
      a.SwapBlockingEdges == b.SwapBlockingEdges &&
      a.StarShapedInStencilPlane == b.StarShapedInStencilPlane &&
      a.SwapMinimumNormalDotWhenBlocked == b.SwapMinimumNormalDotWhenBlocked &&
      a.SwapMinimumNormalDot == b.SwapMinimumNormalDot && a.BatchSearchDepth == b.BatchSearchDepth &&
      a.MinimumNumberOfTriangles == b.MinimumNumberOfTriangles && a.MinimumNormalDot == b.MinimumNormalDot &&
      a.ErrorWeight == b.ErrorWeight && a.QuadricCollapsePoint == b.QuadricCollapsePoint &&
      a.DecideAhead == b.DecideAhead && a.ParallelCollapses == b.ParallelCollapses &&
      a.ParallelBookkeeping == b.ParallelBookkeeping;
  }

  // Hierarchy mesh -> polydata with cell arrays and interpolated point data.
  void ToPolyData(const slod::HierarchyMesh& m, double shownLevel, vtkPolyData* out)
  {
    out->Initialize();
    this->SetPointsAndTriangles(m, out);
    // Each triangle carries the data of the input cell of the M0 triangle it descends from.
    slod::StoreCellData(this->Input, this->TriangleToCell, m.TriangleOrigin, out);
    AddCellArrays(m, shownLevel, out);
    if (!this->Attributes.Empty())
    {
      this->AddPointData(m, out->GetPointData());
    }
  }

  // Points in the input's precision; one triangle per 3 ids.
  void SetPointsAndTriangles(const slod::HierarchyMesh& m, vtkPolyData* out) const
  {
    const vtkIdType np = static_cast<vtkIdType>(m.PointGlobal.size());
    const vtkIdType nt = static_cast<vtkIdType>(m.Triangles.size() / 3);
    vtkNew<vtkPoints> points;
    points->SetDataType(this->PointDataType);
    points->SetNumberOfPoints(np);
    if (this->PointDataType == VTK_DOUBLE && np > 0) // memcpy from/to a null pointer is undefined even for 0 bytes
    {
      double* dst = static_cast<vtkDoubleArray*>(points->GetData())->GetPointer(0);
      std::memcpy(dst, m.Points.data(), sizeof(double) * m.Points.size());
    }
    else if (np > 0)
    {
      float* dst = static_cast<vtkFloatArray*>(points->GetData())->GetPointer(0);
      for (size_t i = 0; i < m.Points.size(); ++i)
      {
        dst[i] = static_cast<float>(m.Points[i]);
      }
    }
    vtkNew<vtkIdTypeArray> offsets, connectivity;
    offsets->SetNumberOfValues(nt + 1);
    connectivity->SetNumberOfValues(3 * nt);
    vtkIdType* off = offsets->GetPointer(0);
    vtkIdType* con = connectivity->GetPointer(0);
    for (vtkIdType i = 0; i <= nt; ++i)
    {
      off[i] = 3 * i;
    }
    for (vtkIdType i = 0; i < 3 * nt; ++i)
    {
      con[i] = m.Triangles[i];
    }
    vtkNew<vtkCellArray> polys;
    polys->SetData(offsets, connectivity);
    out->SetPoints(points);
    out->SetPolys(polys);
  }

  // Per triangle its collapse level, batch and role; the level shown as field data.
  static void AddCellArrays(const slod::HierarchyMesh& m, double shownLevel, vtkPolyData* out)
  {
    const vtkIdType nt = static_cast<vtkIdType>(m.Triangles.size() / 3);
    vtkNew<vtkIntArray> level;
    level->SetName("CollapseLevel");
    level->SetNumberOfValues(nt);
    vtkNew<vtkIntArray> batch;
    batch->SetName("CollapseBatch");
    batch->SetNumberOfValues(nt);
    // Int, not unsigned char: VTK mappers would take unsigned char values as colours.
    vtkNew<vtkIntArray> role;
    role->SetName("CollapseRole");
    role->SetNumberOfValues(nt);
    for (vtkIdType i = 0; i < nt; ++i)
    {
      level->SetValue(i, m.TriangleCollapseLevel[i]);
      batch->SetValue(i, m.TriangleBatch[i]);
      role->SetValue(i, m.TriangleRole[i]);
    }
    out->GetCellData()->AddArray(level);
    out->GetCellData()->AddArray(batch);
    out->GetCellData()->AddArray(role);
    vtkNew<vtkDoubleArray> shown;
    shown->SetName("HierarchyLevel");
    shown->SetNumberOfValues(1);
    shown->SetValue(0, shownLevel);
    out->GetFieldData()->AddArray(shown);
  }

  // Rows of the points; a point blending towards its collapse point gets a row interpolated
  // between the two for BlendT, added for this output only.
  void AddPointData(const slod::HierarchyMesh& m, vtkPointData* pd)
  {
    const slod::Index globalRows = this->Attributes.NumberOfRows();
    this->Rows.assign(m.PointGlobal.begin(), m.PointGlobal.end());
    if (m.BlendT > 0)
    {
      const double weights[2] = { 1.0 - m.BlendT, m.BlendT };
      for (size_t i = 0; i < this->Rows.size(); ++i)
      {
        if (m.PointTarget[i] != slod::InvalidIndex)
        {
          const slod::Index ends[2] = { m.PointGlobal[i], m.PointTarget[i] };
          this->Rows[i] = this->Attributes.AddInterpolated(ends, weights, 2);
        }
      }
    }
    this->Attributes.Store(pd, this->Rows);
    this->Attributes.RemoveRowsFrom(globalRows);
  }

  static slod::CollapseHierarchyParameters ParametersOf(const vtkTriangleCollapseHierarchy& f)
  {
    slod::CollapseHierarchyParameters parameters;
    parameters.CurvatureWeight = f.CurvatureWeight;
    parameters.AngleWeight = f.AngleWeight;
    parameters.ValenceWeight = f.ValenceWeight;
    parameters.BatchFraction = f.BatchFraction;
    parameters.MaximumWeight = f.MaximumWeight;
    parameters.ValenceNormalizer = f.ValenceNormalizer;
    parameters.RemoveCycles = f.RemoveCycles;
    parameters.MaximumNumberOfLevels = f.MaximumNumberOfLevels;
    parameters.MinimumNumberOfTriangles = static_cast<slod::Index>(f.MinimumNumberOfTriangles);
    parameters.MinimumNormalDot = f.MinimumNormalDot;
    parameters.ErrorWeight = f.ErrorWeight;
    parameters.RelaxWhenBlocked = f.RelaxWhenBlocked;
    parameters.PreferEdgeFactor = f.PreferEdgeFactor;
    parameters.PreventNewValenceThree = f.PreventNewValenceThree;
    parameters.VertexErrorWeight = f.VertexErrorWeight;
    parameters.BoundaryWeight = f.BoundaryWeight;
    parameters.EdgeCollapses = static_cast<slod::CollapseHierarchyParameters::EdgeFallback>(f.EdgeCollapses);
    parameters.SwapBlockingEdges = f.SwapBlockingEdges;
    parameters.StarShapedInStencilPlane = f.StarShapedInStencilPlane;
    parameters.SwapMinimumNormalDot = f.SwapMinimumNormalDot;
    parameters.SwapMinimumNormalDotWhenBlocked = f.SwapMinimumNormalDotWhenBlocked;
    parameters.BatchSearchDepth = f.BatchSearchDepth;
    parameters.QuadricCollapsePoint = f.QuadricCollapsePoint;
    parameters.DecideAhead = f.DecideAhead;
    parameters.ParallelCollapses = f.ParallelCollapses;
    parameters.ParallelBookkeeping = f.ParallelBookkeeping;
    return parameters;
  }

  // A missed target: the coarsest level, and the fewest triangles its topology (the input's: the
  // collapses keep it) allows (slod::TopologicalTriangleFloor). Measured on the coarsest mesh, not
  // on M0: the edge topology of a 1M-triangle M0 took 72 bytes per triangle, after the build, the
  // peak memory of a whole hierarchy asked for one triangle.
  static std::string WhyNotReached(const slod::CollapseHierarchy& h)
  {
    slod::TriangleMesh coarsest;
    h.CoarsestMesh().Extract(coarsest);
    const slod::MeshStatistics s = slod::ComputeMeshStatistics(coarsest);
    const long long b = s.BoundaryLoops, chi = s.EulerCharacteristic;
    const long long fewest = slod::TopologicalTriangleFloor(s);
    return "the hierarchy's coarsest level keeps more: further collapses would change the topology or fold a "
           "triangle (keeping " + std::to_string(b) + " border loop(s) and Euler characteristic " +
      std::to_string(chi) + " needs at least about " + std::to_string(fewest) + " triangles)";
  }

  // The triangle count asked for, of n0 input triangles.
  static slod::Index TargetOf(const vtkTriangleCollapseHierarchy& f, slod::Index n0)
  {
    return static_cast<slod::Index>(f.ComputeTargetNumberOfTriangles(n0));
  }

  // Only the target mesh is asked for (no level, no blend, no multiblock of the levels): the
  // hierarchy is built down to the target only (the levels below it were most of the build on
  // MRI isosurfaces and nobody would see them).
  static bool OnlyToTarget(const vtkTriangleCollapseHierarchy& f)
  {
    return !f.GenerateAllLevels && f.Level < 0 && f.ContinuousLevel < 0;
  }

  // The cached hierarchy was built only down to an earlier target: not enough for a lower target
  // or for the levels.
  bool StoppedTooEarly(const vtkTriangleCollapseHierarchy& f) const
  {
    const slod::Index stop = this->Parameters.StopAtTriangles;
    return stop > 0 && (!OnlyToTarget(f) || TargetOf(f, this->Hierarchy.LevelTriangleCount(0)) < stop);
  }

  // The hierarchy of input and its point data (one row per global vertex); false when the input
  // is refused or the build aborted.
  bool Rebuild(vtkTriangleCollapseHierarchy* filter, vtkPolyData* input, slod::CollapseHierarchyParameters parameters)
  {
    this->Valid = false;
    this->Levels = nullptr;
    slod::TriangleMesh mesh;
    std::vector<slod::Index> vertexToInputPoint;
    std::vector<unsigned char> nonManifoldVertices;
    {
      // (The preparation classified the mesh: the build takes its non-manifold flags instead of
      // classifying it again; the rest of the report is not held through the build.)
      slod::PreparationReport report;
      if (!slod::PrepareFilterInput(filter, input, slod::PreparationOptions(), mesh, vertexToInputPoint, &report,
            slod::CellMapIfNeeded(input, this->TriangleToCell)))
      {
        return false;
      }
      nonManifoldVertices = std::move(report.NonManifoldVertexFlags);
    }
    if (input->GetPointData()->GetNumberOfArrays() == 0)
    {
      // Only the point data's transfer reads the map (Attributes.Load, after the build): without
      // point data it is not held through the build (4 bytes per input vertex of its peak).
      std::vector<slod::Index>().swap(vertexToInputPoint);
    }
    parameters.StopAtTriangles = OnlyToTarget(*filter) ? TargetOf(*filter, mesh.NumberOfTriangles()) : 0;
    const auto start = std::chrono::steady_clock::now();
    // (Moved: M0 is this mesh, not a second copy of it.)
    const bool done = this->Hierarchy.Build(
      std::move(mesh), std::move(nonManifoldVertices), parameters, slod::FilterProgress(filter, 0.0, 0.9));
    if (!done)
    {
      return false;
    }
    this->Attributes.Load(input->GetPointData(), vertexToInputPoint);
    if (!this->Attributes.Empty())
    {
      // Row g = global vertex g: collapse points are the mean of the merged vertices.
      const double third[3] = { 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0 }, half[2] = { 0.5, 0.5 };
      for (slod::Index k = 0; k < this->Hierarchy.NumberOfCollapses(); ++k)
      {
        const slod::HierarchyCollapse& c = this->Hierarchy.GetCollapse(k);
        this->Attributes.AddInterpolated(c.Sources, c.Count == 2 ? half : third, c.Count);
      }
    }
    filter->HierarchyBuildTime = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++filter->NumberOfHierarchyBuilds;
    this->Valid = true;
    this->Input = input;
    this->InputTime = input->GetMTime();
    this->Parameters = parameters;
    return true;
  }

  // Output 0's mesh into Scratch: M_i(t) for ContinuousLevel, M_i for Level, else the cut closest
  // to target triangles. Returns the level shown (i + t; for a cut, the fraction of its batch).
  double ExtractShown(const vtkTriangleCollapseHierarchy& f, slod::Index target)
  {
    const slod::CollapseHierarchy& h = this->Hierarchy;
    const int lastLevel = h.NumberOfLevels() - 1;
    if (f.ContinuousLevel >= 0 || (f.Level >= 0 && !f.ExpandFromCoarsestLevel))
    {
      const double shown = f.ContinuousLevel >= 0 ? std::min<double>(f.ContinuousLevel, lastLevel) : std::min(f.Level, lastLevel);
      h.ExtractLevel(shown, this->Scratch);
      return shown;
    }
    if (f.Level >= 0)
    {
      const int level = std::min(f.Level, lastLevel);
      h.Expand(h.LevelStart(level), this->Scratch);
      return level;
    }
    const slod::Index k = h.CollapsesForTriangleCount(target);
    if (f.ExpandFromCoarsestLevel)
    {
      h.Expand(k, this->Scratch);
    }
    else
    {
      h.Extract(k, k, 0.0, this->Scratch);
    }
    const int level = k < h.NumberOfCollapses() ? h.LevelOfCollapse(k) : lastLevel;
    if (level >= lastLevel)
    {
      return lastLevel;
    }
    const double span = h.LevelStart(level + 1) - h.LevelStart(level);
    return level + (span > 0 ? (k - h.LevelStart(level)) / span : 0.0);
  }

  // Output 1: every level M_i as a block (cached with the hierarchy).
  void FillLevels(vtkMultiBlockDataSet* levels)
  {
    const slod::CollapseHierarchy& h = this->Hierarchy;
    if (!this->Levels)
    {
      this->Levels = vtkSmartPointer<vtkMultiBlockDataSet>::New();
      this->Levels->SetNumberOfBlocks(h.NumberOfLevels());
      slod::HierarchyMesh m;
      for (int i = 0; i < h.NumberOfLevels(); ++i)
      {
        h.Extract(h.LevelStart(i), h.LevelStart(i), 0.0, m);
        vtkNew<vtkPolyData> block;
        this->ToPolyData(m, i, block);
        this->Levels->SetBlock(i, block);
        this->Levels->GetMetaData(static_cast<unsigned int>(i))
          ->Set(vtkCompositeDataSet::NAME(), ("Level " + std::to_string(i)).c_str());
      }
    }
    levels->ShallowCopy(this->Levels);
  }
};

//------------------------------------------------------------------------------
vtkTriangleCollapseHierarchy::vtkTriangleCollapseHierarchy()
  : Internal(new Internals)
{
  this->AddSecondaryOutputPort("vtkMultiBlockDataSet");
}

vtkTriangleCollapseHierarchy::~vtkTriangleCollapseHierarchy() = default;

vtkMultiBlockDataSet* vtkTriangleCollapseHierarchy::GetLevelsOutput()
{
  return vtkMultiBlockDataSet::SafeDownCast(this->GetOutputDataObject(1));
}

int vtkTriangleCollapseHierarchy::GetNumberOfLevels() const
{
  return this->Internal->Valid ? this->Internal->Hierarchy.NumberOfLevels() : 0;
}

vtkIdType vtkTriangleCollapseHierarchy::GetLevelNumberOfTriangles(int level) const
{
  if (!this->Internal->Valid || level < 0 || level >= this->Internal->Hierarchy.NumberOfLevels())
  {
    return 0;
  }
  return this->Internal->Hierarchy.LevelTriangleCount(level);
}

vtkIdType vtkTriangleCollapseHierarchy::GetNumberOfCollapses() const
{
  return this->Internal->Valid ? this->Internal->Hierarchy.NumberOfCollapses() : 0;
}

vtkIdType vtkTriangleCollapseHierarchy::GetNumberOfEdgeCollapses() const
{
  return this->Internal->Valid ? this->Internal->Hierarchy.NumberOfEdgeCollapses() : 0;
}

//------------------------------------------------------------------------------
int vtkTriangleCollapseHierarchy::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkMultiBlockDataSet* levels = vtkMultiBlockDataSet::GetData(outputVector, 1);
  Internals& in = *this->Internal;
  if (!input || !output)
  {
    return 1;
  }
  const slod::CollapseHierarchyParameters parameters = Internals::ParametersOf(*this);
  const bool rebuild = !in.Valid || in.Input != input || in.InputTime != input->GetMTime() ||
    !Internals::Same(in.Parameters, parameters) || in.StoppedTooEarly(*this);
  if (rebuild && !in.Rebuild(this, input, parameters))
  {
    if (this->GetAbortExecute())
    {
      slod::ReportAbort(this, output);
    }
    return 1;
  }

  in.PointDataType = slod::OutputPointType(input, this->OutputPointsPrecision);
  // Output 0: the selected mesh.
  const slod::Index target = Internals::TargetOf(*this, in.Hierarchy.LevelTriangleCount(0));
  this->ShownLevel = in.ExtractShown(*this, target);
  in.ToPolyData(in.Scratch, this->ShownLevel, output);
  if (this->ContinuousLevel < 0 && this->Level < 0)
  {
    const bool reached = output->GetNumberOfPolys() <= target;
    slod::ReportTarget(this, output, target, reached, reached ? "" : Internals::WhyNotReached(in.Hierarchy).c_str());
  }
  if (levels)
  {
    levels->Initialize();
    if (this->GenerateAllLevels)
    {
      in.FillLevels(levels);
    }
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkTriangleCollapseHierarchy::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ContinuousLevel: " << this->ContinuousLevel << "\n";
  os << indent << "Level: " << this->Level << "\n";
  os << indent << "CurvatureWeight: " << this->CurvatureWeight << "\n";
  os << indent << "AngleWeight: " << this->AngleWeight << "\n";
  os << indent << "ValenceWeight: " << this->ValenceWeight << "\n";
  os << indent << "ErrorWeight: " << this->ErrorWeight << "\n";
  os << indent << "QuadricCollapsePoint: " << this->QuadricCollapsePoint << "\n";
  os << indent << "RelaxWhenBlocked: " << this->RelaxWhenBlocked << "\n";
  os << indent << "PreventNewValenceThree: " << this->PreventNewValenceThree << "\n";
  os << indent << "EdgeCollapses: " << this->EdgeCollapses << "\n";
  os << indent << "PreferEdgeFactor: " << this->PreferEdgeFactor << "\n";
  os << indent << "VertexErrorWeight: " << this->VertexErrorWeight << "\n";
  os << indent << "BoundaryWeight: " << this->BoundaryWeight << "\n";
  os << indent << "StarShapedInStencilPlane: " << this->StarShapedInStencilPlane << "\n";
  os << indent << "SwapBlockingEdges: " << this->SwapBlockingEdges << "\n";
  os << indent << "SwapMinimumNormalDot: " << this->SwapMinimumNormalDot << "\n";
  os << indent << "SwapMinimumNormalDotWhenBlocked: " << this->SwapMinimumNormalDotWhenBlocked << "\n";
  os << indent << "BatchSearchDepth: " << this->BatchSearchDepth << "\n";
  os << indent << "BatchFraction: " << this->BatchFraction << "\n";
  os << indent << "MaximumWeight: " << this->MaximumWeight << "\n";
  os << indent << "ValenceNormalizer: " << this->ValenceNormalizer << "\n";
  os << indent << "RemoveCycles: " << this->RemoveCycles << "\n";
  os << indent << "MaximumNumberOfLevels: " << this->MaximumNumberOfLevels << "\n";
  os << indent << "MinimumNumberOfTriangles: " << this->MinimumNumberOfTriangles << "\n";
  os << indent << "MinimumNormalDot: " << this->MinimumNormalDot << "\n";
  os << indent << "DecideAhead: " << this->DecideAhead << "\n";
  os << indent << "ParallelCollapses: " << this->ParallelCollapses << "\n";
  os << indent << "ParallelBookkeeping: " << this->ParallelBookkeeping << "\n";
  os << indent << "GenerateAllLevels: " << this->GenerateAllLevels << "\n";
  os << indent << "ExpandFromCoarsestLevel: " << this->ExpandFromCoarsestLevel << "\n";
  os << indent << "NumberOfLevels: " << this->GetNumberOfLevels() << "\n";
  os << indent << "ShownLevel: " << this->ShownLevel << "\n";
}
