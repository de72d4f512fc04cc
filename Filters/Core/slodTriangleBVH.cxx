// Placeholder replaced by the BVH implementation.
#include "slodTriangleBVH.h"
namespace slod
{
void TriangleBVH::Build(const TriangleMesh& mesh) { this->Mesh = &mesh; }
bool TriangleBVH::Empty() const { return true; }
ClosestPointResult TriangleBVH::ClosestPoint(const Vec3&, double) const { return {}; }
Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3&, const Vec3&, const Vec3&) { return p; }
}
