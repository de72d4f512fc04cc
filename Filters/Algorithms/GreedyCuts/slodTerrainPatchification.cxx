// SPDX-License-Identifier: BSD-3-Clause
#include "slodTerrainPatchification.h"

#include "vtkMath.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace slod
{
namespace
{
// The 26 normal classes (i,j,k) in {-1,0,1}^3 \ {0}, with their unit directions.
struct NormalClasses
{
  std::array<std::array<int, 3>, 26> Sign;
  std::array<Vec3, 26> Direction;
  NormalClasses()
  {
    int c = 0;
    for (int i = -1; i <= 1; ++i)
    {
      for (int j = -1; j <= 1; ++j)
      {
        for (int k = -1; k <= 1; ++k)
        {
          if (i != 0 || j != 0 || k != 0)
          {
            this->Sign[c] = { i, j, k };
            this->Direction[c] = Normalized(Vec3{ double(i), double(j), double(k) });
            ++c;
          }
        }
      }
    }
  }
};

const NormalClasses& Classes()
{
  static const NormalClasses classes;
  return classes;
}

// What both stages work on: the mesh, its topology, the parameters and the patch labels.
struct TerrainData
{
  const TriangleMesh& Mesh;
  const MeshTopology& Topology;
  const TerrainPatchificationParameters& Prm;
  std::vector<Index>& Label;
};

// Stage 1: breadth-first growth of one patch at a time.
struct TerrainGrowth : TerrainData
{
  std::vector<Vec3> Normal;
  std::vector<Index> VertexPatch; // last patch that used the vertex (vertices never leave one)
  std::vector<Index> Queue, Rejected;
  // The patch being grown: component ranges of its normals, the smallest dot product with each
  // class direction, its area-weighted normal sum, its fixed class (-1 while free).
  Index Patch = 0;
  double ComponentMin[3], ComponentMax[3];
  std::array<double, 26> ClassMin;
  Vec3 Sum{ 0, 0, 0 };
  int Fixed = -1;

  TerrainGrowth(const TriangleMesh& mesh, const MeshTopology& topology, const TerrainPatchificationParameters& prm,
    std::vector<Index>& label)
    : TerrainData{ mesh, topology, prm, label }
    , Normal(size_t(mesh.NumberOfTriangles()))
    , VertexPatch(size_t(mesh.NumberOfPoints()), InvalidIndex)
  {
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      this->Normal[t] = Normalized(mesh.TriangleAreaVector(t));
    }
  }

  // Width of the angle range of component i (angle between the normals and axis i) if the
  // component spanned [lo, hi].
  static double AngleWidth(double lo, double hi) { return std::acos(std::max(-1.0, lo)) - std::acos(std::min(1.0, hi)); }

  // Class c admits a normal: same sign on the class's non-zero components (the paper's rule) and
  // not seen edge-on from the class direction (our margin against projected slivers).
  bool Admits(int c, const Vec3& n) const
  {
    const auto& sign = Classes().Sign[c];
    for (int i = 0; i < 3; ++i)
    {
      if (sign[i] != 0 && sign[i] * n[i] <= 0)
      {
        return false;
      }
    }
    return Dot(n, Classes().Direction[c]) >= this->Prm.MinimumHeightCosine;
  }

  // A class that admits every triangle of the patch (and the normal *n when given), the closest
  // to the mean normal; -1 when none does.
  int BestClass(const Vec3* n) const
  {
    int best = -1;
    double bestDot = -2;
    for (int c = 0; c < 26; ++c)
    {
      if (this->ClassMin[c] >= this->Prm.MinimumHeightCosine && (!n || this->Admits(c, *n)) &&
        Dot(Classes().Direction[c], this->Sum) > bestDot)
      {
        bestDot = Dot(Classes().Direction[c], this->Sum);
        best = c;
      }
    }
    return best;
  }

  // The disk condition: t touches the patch through one edge whose opposite vertex is new to
  // it, or through two edges.
  bool KeepsDisk(Index t) const
  {
    int shared = 0;
    Index opposite = InvalidIndex;
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index n = this->Topology.EdgeNeighbor(t, k);
      if (n != InvalidIndex && this->Label[n] == this->Patch)
      {
        ++shared;
        opposite = tri[(k + 2) % 3];
      }
    }
    return shared == 2 || (shared == 1 && this->VertexPatch[opposite] != this->Patch);
  }

  // Section 3.4.1, Part 2: free growth while the angle ranges stay within 90 degrees, then the
  // class is fixed and a triangle joins only when the class admits it.
  bool NormalJoins(const Vec3& n)
  {
    if (this->Fixed >= 0)
    {
      return this->Admits(this->Fixed, n);
    }
    bool narrow = true;
    for (int i = 0; i < 3; ++i)
    {
      narrow = narrow &&
        AngleWidth(std::min(this->ComponentMin[i], n[i]), std::max(this->ComponentMax[i], n[i])) <= 0.5 * vtkMath::Pi();
    }
    if (narrow && this->BestClass(&n) >= 0)
    {
      return true;
    }
    // The patch would widen past 90 degrees: its class is fixed from the triangles so far.
    this->Fixed = this->BestClass(nullptr);
    return this->Fixed >= 0 && this->Admits(this->Fixed, n);
  }

  void Add(Index t)
  {
    this->Label[t] = this->Patch;
    const Vec3& n = this->Normal[t];
    for (int i = 0; i < 3; ++i)
    {
      this->ComponentMin[i] = std::min(this->ComponentMin[i], n[i]);
      this->ComponentMax[i] = std::max(this->ComponentMax[i], n[i]);
    }
    for (int c = 0; c < 26; ++c)
    {
      this->ClassMin[c] = std::min(this->ClassMin[c], this->Admits(c, n) ? Dot(n, Classes().Direction[c]) : -1.0);
    }
    this->Sum = this->Sum + this->Mesh.TriangleAreaVector(t);
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      this->VertexPatch[tri[k]] = this->Patch;
    }
    this->Queue.push_back(t);
  }

  // Grows patch `patch` from `seed`; each triangle is examined once per neighbour that joins.
  void Grow(Index patch, Index seed)
  {
    this->Patch = patch;
    this->Fixed = -1;
    this->Sum = { 0, 0, 0 };
    for (int i = 0; i < 3; ++i)
    {
      this->ComponentMin[i] = 1;
      this->ComponentMax[i] = -1;
    }
    this->ClassMin.fill(1.0);
    this->Queue.clear();
    this->Rejected.clear();
    this->Add(seed);
    for (size_t head = 0; head < this->Queue.size(); ++head)
    {
      const Index t = this->Queue[head];
      for (int k = 0; k < 3; ++k)
      {
        const Index n = this->Topology.EdgeNeighbor(t, k);
        if (n == InvalidIndex || this->Label[n] != InvalidIndex)
        {
          continue;
        }
        if (this->KeepsDisk(n) && this->NormalJoins(this->Normal[n]))
        {
          this->Add(n);
        }
        else
        {
          this->Rejected.push_back(n);
        }
      }
    }
  }
};

Index GrowPatches(TerrainGrowth& growth, const ProgressFunction& progress, bool& aborted)
{
  const Index nt = growth.Mesh.NumberOfTriangles();
  growth.Label.assign(size_t(nt), InvalidIndex);
  Index patches = 0, scan = 0, assigned = 0;
  std::vector<Index> seeds;
  for (;;)
  {
    Index seed = InvalidIndex;
    while (!seeds.empty() && seed == InvalidIndex)
    {
      seed = growth.Label[seeds.back()] == InvalidIndex ? seeds.back() : InvalidIndex;
      seeds.pop_back();
    }
    while (seed == InvalidIndex && scan < nt)
    {
      seed = growth.Label[scan] == InvalidIndex ? scan : InvalidIndex;
      ++scan;
    }
    if (seed == InvalidIndex)
    {
      return patches;
    }
    growth.Grow(patches++, seed);
    assigned += static_cast<Index>(growth.Queue.size());
    // The next seed borders the patch just finished: patches follow each other over the surface.
    seeds.insert(seeds.end(), growth.Rejected.rbegin(), growth.Rejected.rend());
    if (progress && !progress(0.8 * double(assigned) / double(std::max<Index>(nt, 1))))
    {
      aborted = true;
      return patches;
    }
  }
}

// Stage 2: small patches merged into a neighbour.
struct PatchMerging : TerrainData
{
  std::vector<std::vector<Index>> Members;
  std::vector<Vec3> Height;
  std::vector<double> HeightMin; // smallest dot of a member's unit normal with Height
  double CosSharp;

  PatchMerging(const TriangleMesh& mesh, const MeshTopology& topology, const TerrainPatchificationParameters& prm,
    std::vector<Index>& label, Index patches)
    : TerrainData{ mesh, topology, prm, label }
    , Members(size_t(patches))
    , Height(size_t(patches), Vec3{ 0, 0, 0 })
    , HeightMin(size_t(patches), 1.0)
    , CosSharp(std::cos(Radians(prm.SharpAngle)))
  {
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      this->Members[label[t]].push_back(t);
    }
    for (Index p = 0; p < patches; ++p)
    {
      this->SetHeight(p);
    }
  }

  Vec3 UnitNormal(Index t) const { return Normalized(this->Mesh.TriangleAreaVector(t)); }

  double MinimumDot(Index p, const Vec3& h) const
  {
    double m = 1.0;
    for (Index t : this->Members[p])
    {
      m = std::min(m, Dot(this->UnitNormal(t), h));
    }
    return m;
  }

  // The height direction: the mean normal when every member faces it well enough, else the
  // admissible class direction (from the growth) with the largest smallest dot product.
  void SetHeight(Index p)
  {
    Vec3 sum{ 0, 0, 0 };
    for (Index t : this->Members[p])
    {
      sum = sum + this->Mesh.TriangleAreaVector(t);
    }
    Vec3 best = Normalized(sum);
    double bestMin = Norm(sum) > 0 ? this->MinimumDot(p, best) : -1.0;
    for (int c = 0; c < 26 && bestMin < this->Prm.MinimumHeightCosine; ++c)
    {
      const double m = this->MinimumDot(p, Classes().Direction[c]);
      if (m > bestMin)
      {
        bestMin = m;
        best = Classes().Direction[c];
      }
    }
    this->Height[p] = best;
    this->HeightMin[p] = bestMin;
  }

  // Whether p and q share exactly one boundary path, no sharp edge on it, and no other vertex
  // (then their union is a disk when both are).
  bool SharesOneSmoothPath(Index p, Index q) const
  {
    std::vector<Index> pathVertices, commonVertices;
    Index edges = 0;
    for (Index t : this->Members[p])
    {
      const Index* tri = this->Mesh.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        const Index n = this->Topology.EdgeNeighbor(t, k);
        if (n != InvalidIndex && this->Label[n] == q)
        {
          if (Dot(this->UnitNormal(t), this->UnitNormal(n)) < this->CosSharp)
          {
            return false;
          }
          ++edges;
          pathVertices.push_back(tri[k]);
          pathVertices.push_back(tri[(k + 1) % 3]);
        }
        bool common = false;
        for (const Index* u = this->Topology.VertexTrianglesBegin(tri[k]); u != this->Topology.VertexTrianglesEnd(tri[k]);
             ++u)
        {
          common = common || this->Label[*u] == q;
        }
        if (common)
        {
          commonVertices.push_back(tri[k]);
        }
      }
    }
    std::sort(pathVertices.begin(), pathVertices.end());
    pathVertices.erase(std::unique(pathVertices.begin(), pathVertices.end()), pathVertices.end());
    std::sort(commonVertices.begin(), commonVertices.end());
    commonVertices.erase(std::unique(commonVertices.begin(), commonVertices.end()), commonVertices.end());
    // A simple open path of e edges has e + 1 vertices; a loop, or several paths, or a vertex
    // touched apart from the path, breaks the count.
    return edges > 0 && pathVertices == commonVertices && Index(pathVertices.size()) == edges + 1;
  }

  bool TryMerge(Index p)
  {
    std::vector<Index> neighbours;
    for (Index t : this->Members[p])
    {
      for (int k = 0; k < 3; ++k)
      {
        const Index n = this->Topology.EdgeNeighbor(t, k);
        if (n != InvalidIndex && this->Label[n] != p)
        {
          neighbours.push_back(this->Label[n]);
        }
      }
    }
    std::sort(neighbours.begin(), neighbours.end());
    neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
    for (Index q : neighbours)
    {
      // The union stays a height field over q's direction (q is the larger patch, or as small).
      if (this->Members[q].size() < this->Members[p].size() || !this->SharesOneSmoothPath(p, q) ||
        this->MinimumDot(p, this->Height[q]) < this->Prm.MinimumHeightCosine)
      {
        continue;
      }
      for (Index t : this->Members[p])
      {
        this->Label[t] = q;
      }
      this->Members[q].insert(this->Members[q].end(), this->Members[p].begin(), this->Members[p].end());
      this->Members[p].clear();
      this->HeightMin[q] = std::min(this->HeightMin[q], this->MinimumDot(q, this->Height[q]));
      return true;
    }
    return false;
  }

  // Smallest patches first; each patch is merged at most once per pass and the passes stop when
  // none merges (every merge removes a patch: at most `patches` merges in all).
  void Run()
  {
    const Index np = static_cast<Index>(this->Members.size());
    for (int pass = 0; pass < 8; ++pass)
    {
      std::vector<std::pair<size_t, Index>> order;
      for (Index p = 0; p < np; ++p)
      {
        if (!this->Members[p].empty() && this->Members[p].size() < size_t(this->Prm.MinimumPatchTriangles))
        {
          order.emplace_back(this->Members[p].size(), p);
        }
      }
      std::sort(order.begin(), order.end());
      bool merged = false;
      for (const auto& [size, p] : order)
      {
        merged = (!this->Members[p].empty() && this->TryMerge(p)) || merged;
      }
      if (!merged)
      {
        return;
      }
    }
  }
};
} // namespace

bool BuildTerrainPatches(const TriangleMesh& mesh, const MeshTopology& topology,
  const TerrainPatchificationParameters& parameters, TerrainPatches& patches, const ProgressFunction& progress)
{
  patches = TerrainPatches();
  std::vector<Index> label;
  TerrainGrowth growth(mesh, topology, parameters, label);
  bool aborted = false;
  const Index grown = GrowPatches(growth, progress, aborted);
  if (aborted)
  {
    return false;
  }
  PatchMerging merging(mesh, topology, parameters, label, grown);
  merging.Run();
  // Stage 3: compact numbering in order of first triangle; final height directions.
  std::vector<Index> renumber(size_t(grown), InvalidIndex);
  patches.TrianglePatch.resize(label.size());
  for (size_t t = 0; t < label.size(); ++t)
  {
    Index& r = renumber[label[t]];
    if (r == InvalidIndex)
    {
      r = patches.NumberOfPatches++;
      merging.SetHeight(label[t]);
      patches.HeightDirection.push_back(merging.Height[label[t]]);
    }
    patches.TrianglePatch[t] = r;
  }
  patches.GrownPatches = grown;
  return !progress || progress(1.0);
}
} // namespace slod
