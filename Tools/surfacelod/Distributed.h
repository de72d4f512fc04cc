// SPDX-License-Identifier: BSD-3-Clause
// `mpiexec -n N surfacelod simplify ...`: the surface simplified in N pieces on VTK's parallel
// engine (vtkMPIController). Rank 0 reads the file and splits it into N spatially coherent pieces,
// sends each rank its piece, every rank simplifies its piece with the method's filter (which keeps
// the seams between pieces: slodPieceSeams.h), and rank 0 gathers the pieces, merges the seam
// points and writes the result. See Documentation/Distributed.md.
#ifndef surfacelodDistributed_h
#define surfacelodDistributed_h

#include "vtkSmartPointer.h"

#include <vector>

class vtkDataObject;
class vtkMPIController;
class vtkMultiProcessController;
class vtkPolyData;

namespace slodcli
{
// MPI for the whole run when the tool was started by mpiexec with more than one process (the one
// place MPI is initialised and finalised): its vtkMPIController becomes VTK's global controller,
// the one the filters use by default. Otherwise it does nothing and the tool runs as a single
// process.
class MpiSession
{
public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

private:
  vtkSmartPointer<vtkMPIController> Controller;
};

// The controller of a distributed run (more than one process), else nullptr.
vtkMultiProcessController* DistributedController();
// This process's rank (0 when not distributed): only rank 0 prints.
int ProcessRank();

// The triangles of `surface` in `count` spatially coherent pieces: sorted by the Morton code of their
// centroids and cut into runs of equal size. Each piece has its own copy of the points it uses (with
// their point data; pieces sharing a point carry identical coordinates) and its cells' data.
std::vector<vtkSmartPointer<vtkPolyData>> SplitIntoPieces(vtkPolyData* surface, int count);

// Rank 0 sends piece r to rank r (r > 0) and returns piece 0; the other ranks return the piece they
// receive. `surface` is used on rank 0 only (released there as the pieces are sent).
vtkSmartPointer<vtkPolyData> ScatterPieces(vtkMultiProcessController* controller, vtkSmartPointer<vtkPolyData> surface);

// The pieces gathered on rank 0 as one surface: points at exactly the same position in two or more
// pieces (the seam vertices the filters kept) become one point; every other point and every cell is
// kept as it is. nullptr on the other ranks.
vtkSmartPointer<vtkPolyData> GatherPieces(vtkMultiProcessController* controller, vtkPolyData* piece);

// Joins pieces into one surface, merging only points that occur in more than one piece.
vtkSmartPointer<vtkPolyData> MergePieces(const std::vector<vtkSmartPointer<vtkDataObject>>& pieces);
} // namespace slodcli

#endif
