// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPLYMeshWriter
 * @brief   writes the surface of a vtkPolyData as PLY with every point and cell array
 *
 * Writes binary (little or big endian) or ASCII PLY. Points keep their precision (float points as
 * float x, y, z, any other type as double); point normals become nx, ny, nz, texture coordinates
 * of two components u, v, unsigned char scalars of three or four components red, green, blue
 * [, alpha]; every other numeric point array becomes vertex properties of its name (NAME_0,
 * NAME_1, ... for several components; an unnamed array is named after its attribute role or its
 * index; white space becomes '_') and of its type (64-bit integers as int when every value fits,
 * else as double). Cell arrays become face properties the same way (cell normals nx, ny, nz,
 * unsigned char colours red, green, blue [, alpha]). vtkPLYMeshReader reads all of it back with
 * the same values, types, components and roles. Polygons are written as they are, strips as
 * triangles (carrying their strip's cell data); vertex and line cells have no face and are not
 * written. Failures (no input, cannot open or write the file) give a vtkErrorMacro naming the
 * file, an error code and GetLastError().
 */
#ifndef vtkPLYMeshWriter_h
#define vtkPLYMeshWriter_h

#include "SurfaceLODFiltersModule.h"
#include "vtkMeshFileWriter.h"

#include <string>

class vtkAbstractArray;
class SURFACELODFILTERS_EXPORT vtkPLYMeshWriter : public vtkMeshFileWriter
{
public:
  static vtkPLYMeshWriter* New();
  vtkTypeMacro(vtkPLYMeshWriter, vtkMeshFileWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// VTK_BINARY (default) or VTK_ASCII.
  vtkSetClampMacro(FileType, int, VTK_ASCII, VTK_BINARY);
  vtkGetMacro(FileType, int);
  void SetFileTypeToASCII() { this->SetFileType(VTK_ASCII); }
  void SetFileTypeToBinary() { this->SetFileType(VTK_BINARY); }

  /// Byte order of a binary file: little endian (default) or big endian.
  vtkSetMacro(BigEndian, bool);
  vtkGetMacro(BigEndian, bool);
  vtkBooleanMacro(BigEndian, bool);

  /// Whether the writer keeps an array (numeric arrays of any type and component count).
  static bool CanWriteArray(vtkAbstractArray* array);

protected:
  vtkPLYMeshWriter() = default;
  ~vtkPLYMeshWriter() override = default;
  std::string WriteMesh(vtkPolyData* mesh, slod::CheckedFileWriter& file) override;
  int FileType = VTK_BINARY;
  bool BigEndian = false;

private:
  vtkPLYMeshWriter(const vtkPLYMeshWriter&) = delete;
  void operator=(const vtkPLYMeshWriter&) = delete;
};

#endif
