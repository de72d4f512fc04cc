// SPDX-License-Identifier: BSD-3-Clause
#include "slodTriangleMesh.h"

#include "slodHugePages.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <limits>

namespace slod
{
Vec3 TriangleMesh::TriangleAreaVector(Index t) const
{
  const Index* tri = this->Triangle(t);
  const Vec3 a = this->Point(tri[0]);
  return Cross(this->Point(tri[1]) - a, this->Point(tri[2]) - a);
}

std::array<double, 6> TriangleMesh::Bounds() const
{
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::array<double, 6> b{ inf, -inf, inf, -inf, inf, -inf };
  for (size_t i = 0; i < this->Points.size(); i += 3)
  {
    for (int k = 0; k < 3; ++k)
    {
      b[2 * k] = std::min(b[2 * k], this->Points[i + k]);
      b[2 * k + 1] = std::max(b[2 * k + 1], this->Points[i + k]);
    }
  }
  return b;
}

double TriangleMesh::BoundingBoxDiagonal() const
{
  if (this->Points.empty())
  {
    return 0.0;
  }
  const auto b = this->Bounds();
  return Norm(Vec3{ b[1] - b[0], b[3] - b[2], b[5] - b[4] });
}

double TriangleMesh::TotalArea() const
{
  double area = 0;
  for (Index t = 0; t < this->NumberOfTriangles(); ++t)
  {
    area += this->TriangleArea(t);
  }
  return area;
}

void TriangleMesh::RemoveUnusedPoints(std::vector<Index>* newToOld)
{
  const Index n = this->NumberOfPoints();
  std::vector<Index> oldToNew(n, InvalidIndex);
  for (Index v : this->Triangles)
  {
    oldToNew[v] = 0;
  }
  Index next = 0;
  if (newToOld)
  {
    newToOld->clear();
  }
  for (Index v = 0; v < n; ++v)
  {
    if (oldToNew[v] != InvalidIndex)
    {
      if (next != v)
      {
        std::copy_n(&this->Points[3 * size_t(v)], 3, &this->Points[3 * size_t(next)]);
      }
      if (newToOld)
      {
        newToOld->push_back(v);
      }
      oldToNew[v] = next++;
    }
  }
  this->Points.resize(3 * size_t(next));
  for (Index& v : this->Triangles)
  {
    v = oldToNew[v];
  }
}

Vec3 TriangleNormal(const Vec3& a, const Vec3& b, const Vec3& c)
{
  return Normalized(Cross(b - a, c - a));
}

double MinimumAngle(const Vec3& a, const Vec3& b, const Vec3& c)
{
  const Vec3 p[3] = { a, b, c };
  double best = 3.5;
  for (int i = 0; i < 3; ++i)
  {
    const Vec3 u = p[(i + 1) % 3] - p[i];
    const Vec3 w = p[(i + 2) % 3] - p[i];
    const double nu = Norm(u), nw = Norm(w);
    if (nu == 0 || nw == 0)
    {
      return 0;
    }
    best = std::min(best, std::atan2(Norm(Cross(u, w)), Dot(u, w)));
  }
  return best;
}

bool IsDegenerate(const Vec3& a, const Vec3& b, const Vec3& c, double relativeTolerance)
{
  return IsDegenerateWithArea(a, b, c, Norm(Cross(b - a, c - a)), relativeTolerance);
}

std::vector<MortonEntry> MortonOrder(const std::vector<double>& centres)
{
  return MortonOrder(static_cast<Index>(centres.size() / 3),
    [&centres](Index id, double* xyz) { std::copy_n(&centres[3 * size_t(id)], 3, xyz); });
}

std::vector<MortonEntry> MortonOrder(Index count, const std::function<void(Index, double*)>& centre)
{
  constexpr double inf = std::numeric_limits<double>::infinity();
  double lo[3] = { inf, inf, inf }, hi[3] = { -inf, -inf, -inf };
  for (Index i = 0; i < count; ++i)
  {
    double c[3];
    centre(i, c);
    for (int k = 0; k < 3; ++k)
    {
      if (std::isfinite(c[k]))
      {
        lo[k] = std::min(lo[k], c[k]);
        hi[k] = std::max(hi[k], c[k]);
      }
    }
  }
  double scale[3];
  for (int k = 0; k < 3; ++k)
  {
    const double extent = hi[k] - lo[k];
    scale[k] = extent > 0 && std::isfinite(extent) ? double((1 << 21) - 1) / extent : 0.0;
  }
  std::vector<MortonEntry> entries = MakeOnHugePages<MortonEntry>(static_cast<size_t>(count));
  auto encode = [&](vtkIdType first, vtkIdType last) {
    for (vtkIdType t = first; t < last; ++t)
    {
      double c[3];
      centre(Index(t), c);
      std::uint64_t code = 0;
      for (int k = 0; k < 3; ++k)
      {
        const double u = std::isfinite(c[k]) ? std::max(0.0, std::min(double((1 << 21) - 1), (c[k] - lo[k]) * scale[k])) : 0.0;
        code |= SpreadBits21(static_cast<std::uint64_t>(u)) << (2 - k);
      }
      entries[size_t(t)] = { code, Index(t) };
    }
  };
  if (count < SerialBelow)
  {
    encode(0, count);
    std::sort(entries.begin(), entries.end());
  }
  else
  {
    vtkSMPTools::For(0, count, encode);
    vtkSMPTools::Sort(entries.begin(), entries.end());
  }
  return entries;
}
} // namespace slod
