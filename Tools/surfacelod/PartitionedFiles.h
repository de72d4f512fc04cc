// SPDX-License-Identifier: BSD-3-Clause
// A surface stored in pieces: a `.pvtp` summary naming one `.vtp` file per piece (VTK's parallel XML
// format, the one ParaView writes and reads). `mpiexec -n N surfacelod simplify IN OUT.pvtp` has
// each process write its own piece (nothing is gathered); a distributed `simplify` started with as
// many processes as the file has pieces reads one piece per process (nothing is scattered); every
// other command reads the pieces as one surface, with the points the pieces share merged.
#ifndef surfacelodPartitionedFiles_h
#define surfacelodPartitionedFiles_h

#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <string>

class vtkMultiProcessController;

namespace slodcli
{
// True for a `.pvtp` path.
bool IsPartitionedPath(const std::string& path);

// The number of pieces the summary names. Throws CliError(ExitData, "PATH: problem").
int PartitionedPieceCount(const std::string& path);

// Piece `piece` of the file's `count` pieces, as stored (may be empty). Throws CliError(ExitData).
vtkSmartPointer<vtkPolyData> ReadPartitionedPiece(const std::string& path, int piece, int count);

// Every piece as one surface: points at exactly the same position in two or more pieces become one
// point (MergePieces). Throws CliError(ExitData).
vtkSmartPointer<vtkPolyData> ReadPartitioned(const std::string& path);

// Writes `piece` as piece r of a `.pvtp` file of N pieces, where r and N are the controller's rank and
// process count (0 and 1 without a controller); rank 0 also writes the summary. The piece files go to
// a folder named after the summary, next to it. Each process then reads its piece back and compares
// its counts (VTK's XML writers do not report a full disk). Collective with a controller: every
// process calls it. Returns "" on success, else the problem (this process's).
std::string WritePartitioned(vtkPolyData* piece, const std::string& path, vtkMultiProcessController* controller);
} // namespace slodcli

#endif
