// SurfaceLOD shared core: bounding-volume hierarchy over triangles for closest-point queries.
// Used by vtkSurfaceDeviation and by any filter that needs distances to the original surface.
#ifndef slodTriangleBVH_h
#define slodTriangleBVH_h

#include "slodTriangleMesh.h"

#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT ClosestPointResult
{
  double Distance2 = 0; // squared distance
  Vec3 Point{ 0, 0, 0 };
  Index Triangle = InvalidIndex;
};

class SURFACELODFILTERS_EXPORT TriangleBVH
{
public:
  TriangleBVH() = default;
  // Keeps a reference to mesh: it must outlive the tree and not change.
  explicit TriangleBVH(const TriangleMesh& mesh) { this->Build(mesh); }
  void Build(const TriangleMesh& mesh);
  bool Empty() const;

  // Closest point on the surface to q. maxDistance2 prunes the search (pass a known upper bound,
  // e.g. the previous query's answer moved by the step, for speed); when nothing lies within it
  // the result has Triangle == InvalidIndex.
  ClosestPointResult ClosestPoint(const Vec3& q, double maxDistance2 = -1) const;

  struct Node
  {
    float Bounds[6]; // xmin,xmax,ymin,ymax,zmin,zmax
    Index First;     // leaf: first entry in Order; inner: index of the left child
    Index Count;     // leaf: number of triangles (> 0); inner: 0 (right child = left child + 1)
  };

private:
  const TriangleMesh* Mesh = nullptr;
  std::vector<Node> Nodes;
  std::vector<Index> Order;
};

// Closest point on triangle (a,b,c) to p.
SURFACELODFILTERS_EXPORT Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
} // namespace slod

#endif
