// SPDX-License-Identifier: BSD-3-Clause
// Mesh files of the `surfacelod` tool: reader/writer chosen by extension, with every failure
// turned into one clean line (VTK's own error messages are captured, not printed).
#ifndef surfacelodMeshIO_h
#define surfacelodMeshIO_h

#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <string>
#include <vector>

namespace slodcli
{
// Replaces VTK's output window: while a capture is active errors and warnings are collected;
// otherwise each is printed as one line "surfacelod: warning: ..." on stderr.
void InstallMessageHandler();

// Collects the VTK errors and warnings raised during its lifetime (nestable).
class MessageCapture
{
public:
  // Warnings are dropped when swallowWarnings (reading files), else printed as usual.
  explicit MessageCapture(bool swallowWarnings = true);
  ~MessageCapture();
  MessageCapture(const MessageCapture&) = delete;
  MessageCapture& operator=(const MessageCapture&) = delete;
  const std::vector<std::string>& Errors() const;
  // First error, or "" when none.
  std::string FirstError() const;
  // The warnings swallowed during its lifetime (to show once their subject is known to be usable).
  std::vector<std::string> HeldWarnings() const;

private:
  size_t Depth;
  size_t WarningDepth;
  bool PreviousSwallow;
};

// Prints "surfacelod: warning: MESSAGE" on stderr.
void PrintWarning(const std::string& message);

// Reads .off .ply .stl .obj .vtp .vtk .pvtp (its pieces as one surface). Throws CliError(ExitData, "PATH: problem") when the file
// is missing, unreadable, of an unsupported type, malformed (checked on its bytes before VTK's
// PLY, STL and OBJ readers see it), refers to missing vertices, has non-finite coordinates on a
// used vertex, or has no triangle with three distinct vertex positions. What a reader would drop
// silently (data after the announced OFF faces, STL facets beyond the announced count) is printed
// as a warning naming the file.
vtkSmartPointer<vtkPolyData> ReadMesh(const std::string& path);

// The first reason `mesh` is no usable surface (no vertices, cell ids out of range, non-finite
// coordinates on a used vertex, no triangle with three distinct positions), "" when it is one.
std::string SurfaceProblem(vtkPolyData* mesh);

// Throws CliError(ExitData) unless PATH has a writable extension and its directory exists.
void CheckWritablePath(const std::string& path);

// Writes .off .ply .stl .obj .vtp .vtk .pvtp (one piece). Throws CliError(ExitData, "PATH: problem"). Point or cell
// arrays the format does not keep are named in one warning (WarnAboutDroppedArrays).
void WriteMesh(vtkPolyData* mesh, const std::string& path);

// Prints one warning naming the point and cell arrays of `mesh` that a file of PATH's type does
// not keep (OBJ keeps the point normals, PLY the texture coordinates, OFF and STL nothing, VTP and
// legacy VTK everything); nothing when all are kept.
void WarnAboutDroppedArrays(vtkPolyData* mesh, const std::string& path);

// Supported extensions, for messages and --help.
std::string ReadableExtensions();
std::string WritableExtensions();

// The polygons and strips of a mesh as triangles only (the mesh itself when it already is).
vtkSmartPointer<vtkPolyData> TriangulatedSurface(vtkPolyData* mesh);
vtkIdType CountTriangles(vtkPolyData* triangles);
} // namespace slodcli

#endif
