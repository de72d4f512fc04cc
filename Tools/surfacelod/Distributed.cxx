// SPDX-License-Identifier: BSD-3-Clause
#include "Distributed.h"

#include "slodTriangleMesh.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkIdList.h"
#include "vtkMPIController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <numeric>

namespace slodcli
{
namespace
{
constexpr int PieceTag = 4101;

// Processes started by mpiexec (Open MPI, or MPICH / Hydra), 1 when not started by it. MPI is
// initialised only for several processes: a single process runs exactly as without mpiexec.
int LaunchedProcessCount()
{
  for (const char* variable : { "OMPI_COMM_WORLD_SIZE", "PMI_SIZE" })
  {
    if (const char* value = std::getenv(variable))
    {
      return std::max(1, std::atoi(value));
    }
  }
  return 1;
}

// Morton code of each triangle's centroid, on a 2^21 grid over the centroids' box.
std::vector<std::uint64_t> CentroidMortonCodes(vtkPolyData* surface)
{
  const vtkIdType n = surface->GetNumberOfPolys();
  std::vector<std::array<double, 3>> centroids(static_cast<size_t>(n));
  vtkCellArray* polys = surface->GetPolys();
  vtkNew<vtkIdList> ids;
  double low[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
  double high[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  for (vtkIdType c = 0; c < n; ++c)
  {
    polys->GetCellAtId(c, ids);
    std::array<double, 3> sum{ 0, 0, 0 };
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      double p[3];
      surface->GetPoint(ids->GetId(k), p);
      for (int i = 0; i < 3; ++i)
      {
        sum[i] += p[i] / double(ids->GetNumberOfIds());
      }
    }
    centroids[c] = sum;
    for (int i = 0; i < 3; ++i)
    {
      low[i] = std::min(low[i], sum[i]);
      high[i] = std::max(high[i], sum[i]);
    }
  }
  std::vector<std::uint64_t> codes(static_cast<size_t>(n));
  for (vtkIdType c = 0; c < n; ++c)
  {
    std::uint64_t code = 0;
    for (int i = 0; i < 3; ++i)
    {
      const double extent = high[i] > low[i] ? high[i] - low[i] : 1.0;
      const auto cell = static_cast<std::uint64_t>((centroids[c][i] - low[i]) / extent * double(0x1fffff));
      code |= slod::SpreadBits21(cell) << i;
    }
    codes[c] = code;
  }
  return codes;
}

// The cells `cells` of `surface` with the points they use, renumbered in order of first use.
vtkSmartPointer<vtkPolyData> ExtractPiece(vtkPolyData* surface, const vtkIdType* cells, vtkIdType count)
{
  auto piece = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataType(surface->GetPoints()->GetDataType());
  vtkNew<vtkCellArray> polys;
  piece->GetPointData()->CopyAllocate(surface->GetPointData());
  piece->GetCellData()->CopyAllocate(surface->GetCellData(), count);
  slod::FirstUseNumbering numbering(static_cast<slod::Index>(surface->GetNumberOfPoints()));
  vtkNew<vtkIdList> ids;
  for (vtkIdType i = 0; i < count; ++i)
  {
    surface->GetPolys()->GetCellAtId(cells[i], ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      const slod::Index before = static_cast<slod::Index>(numbering.Used.size());
      const slod::Index local = numbering(static_cast<slod::Index>(ids->GetId(k)));
      if (local == before) // first use: copy the point and its data
      {
        points->InsertNextPoint(surface->GetPoint(ids->GetId(k)));
        piece->GetPointData()->CopyData(surface->GetPointData(), ids->GetId(k), local);
      }
      ids->SetId(k, local);
    }
    polys->InsertNextCell(ids);
    piece->GetCellData()->CopyData(surface->GetCellData(), cells[i], i);
  }
  piece->SetPoints(points);
  piece->SetPolys(polys);
  return piece;
}

// Old point id -> merged point id: a point at exactly the position of a point of another piece
// takes the id of the first such point; all others keep a point of their own.
std::vector<vtkIdType> SeamPointRepresentatives(vtkPolyData* joined, const std::vector<vtkIdType>& pieceOfPoint)
{
  const vtkIdType n = joined->GetNumberOfPoints();
  std::vector<std::array<double, 3>> positions(static_cast<size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    joined->GetPoint(i, positions[i].data());
  }
  std::vector<vtkIdType> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
    [&](vtkIdType a, vtkIdType b) { return positions[a] != positions[b] ? positions[a] < positions[b] : a < b; });
  std::vector<vtkIdType> representative(static_cast<size_t>(n));
  std::iota(representative.begin(), representative.end(), 0);
  for (size_t start = 0; start < order.size();)
  {
    size_t end = start + 1;
    while (end < order.size() && positions[order[end]] == positions[order[start]])
    {
      ++end;
    }
    // One point per piece joins the group's first point (repeats within a piece stay apart, as the
    // filter left them).
    for (size_t k = start + 1; k < end; ++k)
    {
      const bool pieceSeenBefore = std::any_of(order.begin() + start, order.begin() + k,
        [&](vtkIdType earlier) { return pieceOfPoint[earlier] == pieceOfPoint[order[k]]; });
      if (!pieceSeenBefore)
      {
        representative[order[k]] = order[start];
      }
    }
    start = end;
  }
  return representative;
}

// `joined` with its points replaced by their representatives (unused ones dropped).
vtkSmartPointer<vtkPolyData> WithRepresentativePoints(vtkPolyData* joined, const std::vector<vtkIdType>& representative)
{
  const vtkIdType n = joined->GetNumberOfPoints();
  std::vector<vtkIdType> newId(static_cast<size_t>(n), -1);
  auto merged = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataType(joined->GetPoints()->GetDataType());
  merged->GetPointData()->CopyAllocate(joined->GetPointData());
  for (vtkIdType i = 0; i < n; ++i) // a representative comes before the points it stands for
  {
    if (representative[i] == i)
    {
      newId[i] = points->InsertNextPoint(joined->GetPoint(i));
      merged->GetPointData()->CopyData(joined->GetPointData(), i, newId[i]);
    }
    else
    {
      newId[i] = newId[representative[i]];
    }
  }
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < joined->GetNumberOfPolys(); ++c)
  {
    joined->GetPolys()->GetCellAtId(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      ids->SetId(k, newId[ids->GetId(k)]);
    }
    polys->InsertNextCell(ids);
  }
  merged->SetPoints(points);
  merged->SetPolys(polys);
  merged->GetCellData()->ShallowCopy(joined->GetCellData());
  return merged;
}
} // namespace

MpiSession::MpiSession(int* argc, char*** argv)
{
  if (LaunchedProcessCount() > 1)
  {
    this->Controller = vtkSmartPointer<vtkMPIController>::New();
    this->Controller->Initialize(argc, argv);
    vtkMultiProcessController::SetGlobalController(this->Controller);
  }
}

MpiSession::~MpiSession()
{
  if (this->Controller)
  {
    this->Controller->Finalize();
    vtkMultiProcessController::SetGlobalController(nullptr);
  }
}

vtkMultiProcessController* DistributedController()
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  return controller && controller->GetNumberOfProcesses() > 1 ? controller : nullptr;
}

int ProcessRank()
{
  vtkMultiProcessController* controller = DistributedController();
  return controller ? controller->GetLocalProcessId() : 0;
}

std::vector<vtkSmartPointer<vtkPolyData>> SplitIntoPieces(vtkPolyData* surface, int count)
{
  const vtkIdType n = surface->GetNumberOfPolys();
  const std::vector<std::uint64_t> codes = CentroidMortonCodes(surface);
  std::vector<vtkIdType> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](vtkIdType a, vtkIdType b) { return codes[a] < codes[b]; });
  std::vector<vtkSmartPointer<vtkPolyData>> pieces;
  for (int r = 0; r < count; ++r)
  {
    const vtkIdType begin = n * r / count, end = n * (r + 1) / count;
    pieces.push_back(ExtractPiece(surface, order.data() + begin, end - begin));
  }
  return pieces;
}

vtkSmartPointer<vtkPolyData> ScatterPieces(vtkMultiProcessController* controller, vtkSmartPointer<vtkPolyData> surface)
{
  const int processes = controller->GetNumberOfProcesses();
  if (controller->GetLocalProcessId() != 0)
  {
    auto piece = vtkSmartPointer<vtkPolyData>::New();
    controller->Receive(piece, 0, PieceTag);
    return piece;
  }
  std::vector<vtkSmartPointer<vtkPolyData>> pieces = SplitIntoPieces(surface, processes);
  surface = nullptr;
  for (int r = 1; r < processes; ++r)
  {
    controller->Send(pieces[r], r, PieceTag);
    pieces[r] = nullptr; // sent: release it
  }
  return pieces[0];
}

vtkSmartPointer<vtkPolyData> GatherPieces(vtkMultiProcessController* controller, vtkPolyData* piece)
{
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  controller->Gather(piece, pieces, 0);
  return controller->GetLocalProcessId() == 0 ? MergePieces(pieces) : nullptr;
}

vtkSmartPointer<vtkPolyData> MergePieces(const std::vector<vtkSmartPointer<vtkDataObject>>& pieces)
{
  vtkNew<vtkAppendPolyData> append;
  std::vector<vtkIdType> pieceOfPoint;
  for (size_t r = 0; r < pieces.size(); ++r)
  {
    vtkPolyData* piece = vtkPolyData::SafeDownCast(pieces[r]);
    if (piece && piece->GetNumberOfPoints() > 0)
    {
      append->AddInputData(piece);
      pieceOfPoint.insert(pieceOfPoint.end(), static_cast<size_t>(piece->GetNumberOfPoints()), vtkIdType(r));
    }
  }
  if (pieceOfPoint.empty())
  {
    return vtkSmartPointer<vtkPolyData>::New();
  }
  append->Update();
  vtkPolyData* joined = append->GetOutput();
  return WithRepresentativePoints(joined, SeamPointRepresentatives(joined, pieceOfPoint));
}
} // namespace slodcli
