// SPDX-License-Identifier: BSD-3-Clause
#include "vtkOFFMeshWriter.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <charconv>
#include <cstdio>
#include <memory>
#include <vector>

vtkStandardNewMacro(vtkOFFMeshWriter);

namespace
{
// Appends the shortest round-trip decimal form of a value.
template <typename Real>
char* AppendReal(char* out, char* end, Real value)
{
  return std::to_chars(out, end, value).ptr;
}

char* AppendInteger(char* out, char* end, long long value)
{
  return std::to_chars(out, end, value).ptr;
}

struct FileCloser
{
  void operator()(FILE* f) const
  {
    if (f)
    {
      std::fclose(f);
    }
  }
};
} // namespace

void vtkOFFMeshWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

int vtkOFFMeshWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

vtkPolyData* vtkOFFMeshWriter::GetInput()
{
  return vtkPolyData::SafeDownCast(this->Superclass::GetInput());
}

void vtkOFFMeshWriter::WriteData()
{
  this->LastError.clear();
  this->SetErrorCode(vtkErrorCode::NoError);
  auto fail = [&](const std::string& message, unsigned long code) {
    this->LastError = this->FileName + ": " + message;
    vtkErrorMacro(<< this->LastError);
    this->SetErrorCode(code);
  };

  vtkPolyData* input = this->GetInput();
  if (!input)
  {
    fail("no input to write", vtkErrorCode::UnknownError);
    return;
  }
  if (this->FileName.empty())
  {
    fail("no file name", vtkErrorCode::NoFileNameError);
    return;
  }
  std::unique_ptr<FILE, FileCloser> file(std::fopen(this->FileName.c_str(), "wb"));
  if (!file)
  {
    fail("cannot open file for writing", vtkErrorCode::CannotOpenFileError);
    return;
  }

  const vtkIdType numPoints = input->GetNumberOfPoints();
  vtkDataArray* coordinates = input->GetPoints() ? input->GetPoints()->GetData() : nullptr;
  const bool floatPoints = coordinates && coordinates->GetDataType() == VTK_FLOAT;

  // Faces: polygons as they are, strips split into triangles.
  vtkCellArray* polys = input->GetPolys();
  vtkCellArray* strips = input->GetStrips();
  vtkIdType stripTriangles = 0;
  {
    auto it = vtk::TakeSmartPointer(strips->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      stripTriangles += n > 2 ? n - 2 : 0;
    }
  }
  const vtkIdType numFaces = polys->GetNumberOfCells() + stripTriangles;

  std::vector<char> buffer(1 << 16);
  char* const begin = buffer.data();
  char* const limit = begin + buffer.size() - 256; // room for one more record
  char* const end = begin + buffer.size();
  char* out = begin;
  bool ok = true;
  auto flush = [&](bool force) {
    if (force || out >= limit)
    {
      const size_t size = static_cast<size_t>(out - begin);
      ok = ok && std::fwrite(begin, 1, size, file.get()) == size;
      out = begin;
    }
  };

  out += std::snprintf(out, 128, "OFF\n%lld %lld 0\n", static_cast<long long>(numPoints),
    static_cast<long long>(numFaces));
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    double p[3];
    coordinates->GetTuple(i, p);
    for (int a = 0; a < 3; ++a)
    {
      out = floatPoints ? AppendReal(out, end, static_cast<float>(p[a])) : AppendReal(out, end, p[a]);
      *out++ = a < 2 ? ' ' : '\n';
    }
    flush(false);
  }
  auto writeFace = [&](vtkIdType n, const vtkIdType* ids) {
    out = AppendInteger(out, end, n);
    for (vtkIdType k = 0; k < n; ++k)
    {
      *out++ = ' ';
      out = AppendInteger(out, end, ids[k]);
      if (out >= limit)
      {
        flush(true); // very large polygons
      }
    }
    *out++ = '\n';
    flush(false);
  };
  {
    auto it = vtk::TakeSmartPointer(polys->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      writeFace(n, ids);
    }
  }
  {
    auto it = vtk::TakeSmartPointer(strips->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      for (vtkIdType k = 0; k + 2 < n; ++k)
      {
        // Alternate the winding so every strip triangle keeps the strip's orientation.
        const vtkIdType tri[3] = { ids[k], ids[k + 1 + (k & 1)], ids[k + 2 - (k & 1)] };
        writeFace(3, tri);
      }
    }
  }
  flush(true);
  ok = ok && std::fflush(file.get()) == 0;
  if (!ok)
  {
    fail("write failed (disk full?)", vtkErrorCode::OutOfDiskSpaceError);
    return;
  }
  if (std::fclose(file.release()) != 0)
  {
    fail("write failed while closing the file", vtkErrorCode::OutOfDiskSpaceError);
  }
}
