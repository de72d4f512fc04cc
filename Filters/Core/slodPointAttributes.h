// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: point data carried through simplification.
//
// All numeric point arrays of the input, named or not (with a value for every point; the first of
// several of one name), keeping their attribute role (normals, texture coordinates...), are copied into one flat double buffer (one row per
// mesh vertex), merged as vertices merge (weighted average), and written back to VTK arrays of
// the original types for the output vertices.
#ifndef slodPointAttributes_h
#define slodPointAttributes_h

#include "slodTriangleMesh.h"

#include <string>
#include <vector>

class vtkPointData;

namespace slod
{
class SURFACELODFILTERS_EXPORT PointAttributes
{
public:
  // rowToInputPoint[i] is the input point id that mesh vertex i came from.
  void Load(vtkPointData* input, const std::vector<Index>& rowToInputPoint);
  bool Empty() const { return this->Width == 0; }
  int GetWidth() const { return this->Width; }
  Index NumberOfRows() const { return this->Width ? static_cast<Index>(this->Values.size() / this->Width) : 0; }

  // Row `target` becomes sum(weights[i] * row(sources[i])) / sum(weights). target may be a source.
  void Merge(Index target, const Index* sources, const double* weights, int count);
  // Appends a row interpolated from existing rows (e.g. a new vertex); returns its index.
  Index AddInterpolated(const Index* sources, const double* weights, int count);
  const double* Row(Index r) const { return &this->Values[size_t(r) * this->Width]; }

  // Output arrays (same names, types and component counts as the input) for the given rows.
  void Store(vtkPointData* output, const std::vector<Index>& outputToRow) const;

private:
  struct ArrayInfo
  {
    std::string Name;
    bool Named = true;
    int InputIndex = 0;
    int DataType = 0;
    int Components = 0;
    int Offset = 0;
    int AttributeType = -1; // vtkDataSetAttributes attribute (normals, scalars...) or -1
  };
  std::vector<ArrayInfo> Arrays;
  std::vector<double> Values;
  std::vector<double> Temp;
  int Width = 0;
};
} // namespace slod

#endif
