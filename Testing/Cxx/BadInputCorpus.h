// SPDX-License-Identifier: BSD-3-Clause
// The bad-input corpus of the SurfaceLOD test suite: deterministic vtkPolyData inputs of every kind
// of bad or awkward surface users feed in (empty, no triangles, polygons and strips, non-manifold
// and non-orientable surfaces, NaN / huge / tiny coordinates, 10,000 components, valence 5,000,
// every kind of point data, cell ids out of range...), the same as files plus broken files for the
// command-line tool, and an independent check of what a filter made of an input.
#ifndef SurfaceLODBadInputCorpus_h
#define SurfaceLODBadInputCorpus_h

#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <string>
#include <vector>

namespace slodtest
{
struct BadInput
{
  std::string Name;
  vtkSmartPointer<vtkPolyData> Surface;
  // A used point is not finite: every filter must report an error and give an empty output.
  bool Unusable = false;
  // Some cell refers to a point that does not exist (negative or too large): the reference
  // counts below are unknown, so only "error and empty output, or a valid output" is checked.
  bool InvalidCellIds = false;
};

// Names of every category, in a fixed order.
std::vector<std::string> BadInputNames();
// The input of a category (deterministic); throws std::invalid_argument for an unknown name.
BadInput MakeBadInput(const std::string& name);

// What a surface is made of, counted independently of the project's input preparation: the
// polygons, strips and triangles fan-triangulated, points merged by exact coordinates, triangles
// with a repeated vertex or a duplicate vertex set dropped (as the input contract says; triangles
// of zero area with three distinct vertices are kept, and counted apart).
struct SurfaceCensus
{
  long long Triangles = 0;
  long long TrianglesWithArea = 0; // of them, those of non-zero area
  // Triangles of three distinct point ids, exact repeats (the same cycle) once, points not merged:
  // what the input contract may keep (coincident points stay apart unless they seal a border, a
  // triangle and its mirror image are both kept), the bound on an output's triangle count.
  long long DistinctTriangles = 0;
  long long BorderEdges = 0;      // edges of one triangle
  long long NonManifoldEdges = 0; // edges of three or more triangles
  bool Closed() const { return this->Triangles > 0 && this->BorderEdges == 0; }
};
SurfaceCensus CountSurface(vtkPolyData* surface);

struct OutputExpectations
{
  bool MayOpen = false;              // the filter may cut a closed surface open (topology simplification)
  bool MayAddNonManifoldEdges = false; // a VTK baseline (vtkQuadricDecimation) that makes no topology promise
  bool CarriesPointData = true;      // every named numeric point array of the input must be in the output
  bool MayNotGrow = true;            // at most as many triangles as the input
};

// The problems of `output`, made by a filter from `input` that reported `errors` errors; empty when
// the output is acceptable: either an error and no cells, or no error and a valid surface (finite
// points, triangles only, valid ids, no more triangles than the input, no new non-manifold edge, a
// closed input stays closed, the point arrays carried, not emptied).
std::vector<std::string> CheckFilterOutput(const BadInput& input, vtkPolyData* output, int errors,
  const OutputExpectations& expectations);

// Writes every category as NAME.vtk (legacy binary) into `directory`, plus the broken files of the file-level
// corpus as broken-NAME.EXT (empty, header only, truncated, wrong counts, bad indices, wrong byte
// order, NaN in OBJ...), each of which a reader must refuse. Returns the paths written.
std::vector<std::string> WriteBadInputFiles(const std::string& directory);
} // namespace slodtest

#endif
