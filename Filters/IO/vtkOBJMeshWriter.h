// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkOBJMeshWriter
 * @brief   writes the surface of a vtkPolyData as Wavefront OBJ with normals and texture coordinates
 *
 * Writes "v" lines (the shortest decimals that read back to the same value in the points'
 * precision), "vt" lines for point texture coordinates of two components, "vn" lines for point
 * normals, and "f" lines (polygons as they are, strips as triangles) whose corners use the same
 * number for position, texture coordinate and normal. vtkOBJMeshReader reads it back with the
 * same points, polygons and values. Other arrays, cell data, vertex and line cells have no OBJ
 * form and are not written. Failures (no input, cannot open or write the file) give a
 * vtkErrorMacro naming the file, an error code and GetLastError().
 */
#ifndef vtkOBJMeshWriter_h
#define vtkOBJMeshWriter_h

#include "SurfaceLODFiltersModule.h"
#include "vtkWriter.h"

#include <string>

class vtkPolyData;

class SURFACELODFILTERS_EXPORT vtkOBJMeshWriter : public vtkWriter
{
public:
  static vtkOBJMeshWriter* New();
  vtkTypeMacro(vtkOBJMeshWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);

  /// Description of the last failure ("" when the last write succeeded).
  const char* GetLastError() const { return this->LastError.c_str(); }

  vtkPolyData* GetInput();

protected:
  vtkOBJMeshWriter() = default;
  ~vtkOBJMeshWriter() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  std::string FileName;
  std::string LastError;

private:
  vtkOBJMeshWriter(const vtkOBJMeshWriter&) = delete;
  void operator=(const vtkOBJMeshWriter&) = delete;
};

#endif
