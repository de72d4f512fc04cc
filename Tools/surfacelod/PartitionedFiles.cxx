// SPDX-License-Identifier: BSD-3-Clause
#include "PartitionedFiles.h"

#include "CliSupport.h"
#include "Distributed.h"
#include "MeshIO.h"

#include "vtkErrorCode.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkXMLPPolyDataReader.h"
#include "vtkXMLPPolyDataWriter.h"

#include <filesystem>
#include <vector>

namespace slodcli
{
namespace
{
// The reader's first captured error, else its error code's text, else "".
std::string ReaderProblem(vtkXMLPPolyDataReader* reader, const MessageCapture& capture)
{
  if (!capture.FirstError().empty())
  {
    return capture.FirstError();
  }
  return reader->GetErrorCode() != vtkErrorCode::NoError ? vtkErrorCode::GetStringFromErrorCode(reader->GetErrorCode())
                                                         : std::string();
}

vtkSmartPointer<vtkXMLPPolyDataReader> OpenSummary(const std::string& path)
{
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
  {
    throw CliError(ExitData, path + ": no such file");
  }
  auto reader = vtkSmartPointer<vtkXMLPPolyDataReader>::New();
  reader->SetFileName(path.c_str());
  MessageCapture capture;
  reader->UpdateInformation();
  const std::string problem = ReaderProblem(reader, capture);
  if (!problem.empty() || reader->GetNumberOfPieces() < 1)
  {
    throw CliError(ExitData, path + ": not a readable .pvtp summary" + (problem.empty() ? "" : " (" + problem + ")"));
  }
  return reader;
}

vtkSmartPointer<vtkPolyData> ReadPiece(vtkXMLPPolyDataReader* reader, const std::string& path, int piece, int count)
{
  MessageCapture capture;
  reader->UpdatePiece(piece, count, 0);
  const std::string problem = ReaderProblem(reader, capture);
  if (!problem.empty())
  {
    throw CliError(ExitData, path + ": piece " + std::to_string(piece) + ": " + problem);
  }
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->ShallowCopy(reader->GetOutput());
  return result;
}
} // namespace

bool IsPartitionedPath(const std::string& path)
{
  return std::filesystem::path(path).extension() == ".pvtp";
}

int PartitionedPieceCount(const std::string& path)
{
  return OpenSummary(path)->GetNumberOfPieces();
}

vtkSmartPointer<vtkPolyData> ReadPartitionedPiece(const std::string& path, int piece, int count)
{
  return ReadPiece(OpenSummary(path), path, piece, count);
}

vtkSmartPointer<vtkPolyData> ReadPartitioned(const std::string& path)
{
  vtkSmartPointer<vtkXMLPPolyDataReader> reader = OpenSummary(path);
  const int count = reader->GetNumberOfPieces();
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  for (int piece = 0; piece < count; ++piece)
  {
    pieces.push_back(ReadPiece(reader, path, piece, count));
  }
  return MergePieces(pieces);
}

std::string WritePartitioned(vtkPolyData* piece, const std::string& path, vtkMultiProcessController* controller)
{
  const int rank = controller ? controller->GetLocalProcessId() : 0;
  const int count = controller ? controller->GetNumberOfProcesses() : 1;
  std::string problem;
  {
    MessageCapture capture;
    vtkNew<vtkXMLPPolyDataWriter> writer;
    writer->SetInputData(piece);
    writer->SetFileName(path.c_str());
    writer->SetUseSubdirectory(true);
    writer->SetNumberOfPieces(count);
    writer->SetStartPiece(rank);
    writer->SetEndPiece(rank);
    writer->SetController(controller);
    writer->SetDataModeToAppended();
    const int ok = writer->Write();
    problem = !capture.FirstError().empty() ? capture.FirstError()
      : (!ok || writer->GetErrorCode() != vtkErrorCode::NoError)
      ? std::string("writer failed: ") + vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode())
      : std::string();
  }
  if (controller)
  {
    controller->Barrier(); // the summary (rank 0) exists before anyone reads it back
  }
  if (!problem.empty())
  {
    return problem;
  }
  try
  {
    vtkSmartPointer<vtkPolyData> back = ReadPartitionedPiece(path, rank, count);
    if (back->GetNumberOfPoints() != piece->GetNumberOfPoints() || back->GetNumberOfCells() != piece->GetNumberOfCells())
    {
      return "piece " + std::to_string(rank) + " reads back with " + std::to_string(back->GetNumberOfCells()) +
        " cells instead of " + std::to_string(piece->GetNumberOfCells()) + " (disk full?)";
    }
  }
  catch (const CliError& e)
  {
    return std::string("reading it back failed: ") + e.what();
  }
  return std::string();
}
} // namespace slodcli
