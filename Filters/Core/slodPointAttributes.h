// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: point data carried through simplification.
//
// Every point array of the input, named or not (with a value for every point; the first of several
// of one name), is held as rows (one per mesh vertex, then one per added vertex) in a vtkPointData
// of the input's array types and attribute roles. Merges and new vertices go through VTK's own
// interpolation (vtkDataSetAttributes::InterpolatePoint) and so follow VTK's conventions:
//  - floating-point arrays are weighted averages; integer arrays are rounded to an integer;
//  - global and pedigree ids are labels: the heaviest source's id is taken (VTK's nearest-neighbour
//    mode), never an average;
//  - vtkIdType arrays (e.g. vtkIdFilter's ids), which VTK never interpolates, are likewise copied
//    from the heaviest source;
//  - string arrays take the heaviest source's value.
// Nothing is renormalised by the interpolation; Store renormalises the normals (averaged unit
// normals are shorter than one).
#ifndef slodPointAttributes_h
#define slodPointAttributes_h

#include "slodTriangleMesh.h"

#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <vector>

class vtkIdList;
class vtkPointData;

namespace slod
{
class SURFACELODFILTERS_EXPORT PointAttributes
{
public:
  PointAttributes();
  ~PointAttributes();

  // rowToInputPoint[i] is the input point id that mesh vertex i came from.
  void Load(vtkPointData* input, const std::vector<Index>& rowToInputPoint);
  bool Empty() const;
  int GetNumberOfArrays() const;
  Index NumberOfRows() const { return this->Rows; }

  // Row `target` becomes the interpolation of rows sources[i] with weights[i] (normalised; equal
  // weights when they sum to zero). target may be a source.
  void Merge(Index target, const Index* sources, const double* weights, int count);
  // Appends a row interpolated from existing rows (e.g. a new vertex); returns its index.
  Index AddInterpolated(const Index* sources, const double* weights, int count);
  // Drops the rows from `rows` on (e.g. rows added for one output only).
  void RemoveRowsFrom(Index rows);

  // Output arrays (same names, types, component counts and roles as the input) for the given
  // rows, normals renormalised.
  void Store(vtkPointData* output, const std::vector<Index>& outputToRow) const;

  // Scales every tuple of the normals of `pointData` (if any) to unit length.
  static void RenormalizeNormals(vtkPointData* pointData);

private:
  void InterpolateInto(Index target, const Index* sources, const double* weights, int count);

  vtkSmartPointer<vtkPointData> Data;    // one tuple per row
  vtkSmartPointer<vtkPointData> Scratch; // one tuple: an interpolation before it is stored in its row
  std::vector<int> ScratchArrayOf;       // per array of Data: its array in Scratch, -1 if not interpolated
  vtkNew<vtkIdList> Ids;
  std::vector<double> Weights;
  Index Rows = 0;
};
} // namespace slod

#endif
