#include "slodPatchification.h"

#include <algorithm>
#include <cmath>

namespace slod
{
namespace
{
constexpr double DegreesToRadians = 3.14159265358979323846 / 180.0;

} // namespace

// The adjacency the growth needs, as one flat array: the triangle across edge k of t when that
// edge is manifold and consistently oriented (the neighbour runs it the other way), else
// InvalidIndex. Growing only across such edges keeps every patch an orientable disk.
struct Patchification::Adjacency
{
  std::vector<Index> Across;

  Adjacency(const TriangleMesh& mesh, const MeshTopology& topology)
  {
    const Index nt = mesh.NumberOfTriangles();
    this->Across.resize(3 * size_t(nt));
    for (Index t = 0; t < nt; ++t)
    {
      const Index* tri = mesh.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        Index n = topology.EdgeNeighbor(t, k);
        if (n != InvalidIndex)
        {
          const Index a = tri[k], b = tri[(k + 1) % 3];
          const Index* other = mesh.Triangle(n);
          const bool consistent = (other[0] == b && other[1] == a) || (other[1] == b && other[2] == a) ||
            (other[2] == b && other[0] == a);
          n = consistent ? n : InvalidIndex;
        }
        this->Across[3 * size_t(t) + k] = n;
      }
    }
  }
  Index Neighbor(Index t, int k) const { return this->Across[3 * size_t(t) + k]; }
};

void Patchification::Build(const TriangleMesh& mesh, const MeshTopology& topology,
  const PatchificationParameters& parameters, const ProgressFunction& progress)
{
  this->WasAborted = false;
  const Adjacency adjacency(mesh, topology);
  this->Grow(mesh, adjacency, parameters, progress);
  if (this->WasAborted)
  {
    return;
  }
  this->ExtractChains(mesh, topology, adjacency);
}

void Patchification::BuildFromLabels(
  const TriangleMesh& mesh, const MeshTopology& topology, const std::vector<Index>& patchOf, Index numberOfPatches)
{
  this->WasAborted = false;
  const Adjacency adjacency(mesh, topology);
  this->TrianglePatch = patchOf;
  this->PatchAreaVector.assign(size_t(numberOfPatches), Vec3{ 0.0, 0.0, 0.0 });
  this->PatchAreaOf.assign(size_t(numberOfPatches), 0.0);
  this->PatchTriangleCountOf.assign(size_t(numberOfPatches), 0);
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    const Vec3 a = mesh.Point(tri[0]), b = mesh.Point(tri[1]), c = mesh.Point(tri[2]);
    const Vec3 areaVector = 0.5 * Cross(b - a, c - a);
    const Index p = patchOf[t];
    this->PatchAreaVector[p] = this->PatchAreaVector[p] + areaVector;
    this->PatchAreaOf[p] += Norm(areaVector);
    ++this->PatchTriangleCountOf[p];
  }
  this->ExtractChains(mesh, topology, adjacency);
}

// Breadth-first growth with the four cases of section 4.2.2. The disk invariant is kept exactly:
// a triangle sharing one edge with P joins only when its third vertex is not yet in P (no pinch,
// feasibility test (a)); one sharing two edges closes a notch; one sharing three never joins; a
// triangle is removed again (case "two free neighbours, infeasible") only when it hangs on P by
// one edge and its opposite vertex belongs to no other triangle of P. A removed triangle may
// rejoin P later only through two shared edges (a notch).
void Patchification::Grow(const TriangleMesh& mesh, const Adjacency& adjacency,
  const PatchificationParameters& parameters, const ProgressFunction& progress)
{
  const Index nt = mesh.NumberOfTriangles();
  const Index nv = mesh.NumberOfPoints();
  this->TrianglePatch.assign(size_t(nt), InvalidIndex);
  this->PatchAreaVector.clear();
  this->PatchAreaOf.clear();
  this->PatchTriangleCountOf.clear();

  const double cosOnePatch = std::cos(parameters.OneEdgePatchAngle * DegreesToRadians);
  const double cosOneNeighbor = std::cos(parameters.OneEdgeNeighborAngle * DegreesToRadians);
  const double cosTwoPatch = std::cos(parameters.TwoEdgePatchAngle * DegreesToRadians);
  const double cosTwoNeighbor = std::cos(parameters.TwoEdgeNeighborAngle * DegreesToRadians);

  // Membership of vertices in the patch being grown: stamp + number of its triangles there.
  std::vector<Index> vertexStamp(size_t(nv), InvalidIndex);
  std::vector<Index> vertexCount(size_t(nv), 0);
  // Patch that last owned a triangle: a triangle removed from P never rejoins P (termination).
  std::vector<Index> triedStamp(size_t(nt), InvalidIndex);
  std::vector<Index> queue;
  std::vector<Index> rejected;   // free neighbours met by the current patch: next seeds
  std::vector<Index> candidates; // older seed candidates
  Index scan = 0;
  Index assigned = 0;
  Index nextReport = 65536;

  Index patch = InvalidIndex;
  Vec3 sum{ 0, 0, 0 };
  Vec3 centroidSum{ 0, 0, 0 }; // area-weighted
  double area = 0;
  const double maximumDistance = parameters.MaximumPlaneDistance;
  Index count = 0;

  auto weightOf = [&](Index t, Vec3& areaVector) {
    areaVector = mesh.TriangleAreaVector(t);
    return parameters.AreaWeighted ? areaVector : Normalized(areaVector);
  };
  auto inPatch = [&](Index v) { return vertexStamp[v] == patch && vertexCount[v] > 0; };
  auto add = [&](Index t) {
    this->TrianglePatch[t] = patch;
    triedStamp[t] = patch;
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      if (vertexStamp[tri[k]] != patch)
      {
        vertexStamp[tri[k]] = patch;
        vertexCount[tri[k]] = 0;
      }
      ++vertexCount[tri[k]];
    }
    Vec3 av;
    sum = sum + weightOf(t, av);
    area += 0.5 * Norm(av);
    centroidSum = centroidSum + (Norm(av) / 6.0) * (mesh.Point(tri[0]) + mesh.Point(tri[1]) + mesh.Point(tri[2]));
    ++count;
    ++assigned;
    queue.push_back(t);
  };
  auto remove = [&](Index t) {
    this->TrianglePatch[t] = InvalidIndex;
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      --vertexCount[tri[k]];
    }
    Vec3 av;
    sum = sum - weightOf(t, av);
    area -= 0.5 * Norm(av);
    centroidSum = centroidSum - (Norm(av) / 6.0) * (mesh.Point(tri[0]) + mesh.Point(tri[1]) + mesh.Point(tri[2]));
    --count;
    --assigned;
  };
  // Edges of t shared with the current patch; `opposite` gets the vertex opposite the shared
  // edge when there is exactly one.
  auto sharedEdges = [&](Index t, Index& opposite) {
    int shared = 0;
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index n = adjacency.Neighbor(t, k);
      if (n != InvalidIndex && this->TrianglePatch[n] == patch)
      {
        ++shared;
        opposite = tri[(k + 2) % 3];
      }
    }
    return shared;
  };
  auto feasible = [&](Index t, Index candidate) {
    Index opposite = InvalidIndex;
    const int shared = sharedEdges(candidate, opposite);
    if (shared >= 3 || shared == 0)
    {
      return false;
    }
    if (triedStamp[candidate] == patch && shared < 2)
    {
      // Removed from this patch before: it may come back only to fill a notch (two shared
      // edges), after which it can never be removed again (termination).
      return false;
    }
    if (shared == 1 && inPatch(opposite))
    {
      return false; // (a) would pinch the patch boundary
    }
    const Vec3 nc = Normalized(mesh.TriangleAreaVector(candidate));
    const Vec3 nt = Normalized(mesh.TriangleAreaVector(t));
    const Vec3 np = Normalized(sum);
    if (maximumDistance > 0 && shared == 1 && area > 0)
    {
      const Vec3 centroid = (1.0 / area) * centroidSum;
      if (std::fabs(Dot(mesh.Point(opposite) - centroid, np)) > maximumDistance)
      {
        return false; // the patch would bend away from its plane
      }
    }
    const double cosPatch = shared == 1 ? cosOnePatch : cosTwoPatch;
    const double cosNeighbor = shared == 1 ? cosOneNeighbor : cosTwoNeighbor;
    return Dot(nc, np) >= cosPatch && Dot(nc, nt) >= cosNeighbor; // (b)
  };

  Index seed = nt > 0 ? 0 : InvalidIndex;
  while (seed != InvalidIndex)
  {
    patch = static_cast<Index>(this->PatchAreaVector.size());
    sum = { 0, 0, 0 };
    centroidSum = { 0, 0, 0 };
    area = 0;
    count = 0;
    queue.clear();
    rejected.clear();
    add(seed);
    for (size_t head = 0; head < queue.size(); ++head)
    {
      const Index t = queue[head];
      if (this->TrianglePatch[t] != patch)
      {
        continue; // removed meanwhile
      }
      Index freeNeighbors[3];
      int freeCount = 0;
      for (int k = 0; k < 3; ++k)
      {
        const Index n = adjacency.Neighbor(t, k);
        if (n != InvalidIndex && this->TrianglePatch[n] == InvalidIndex)
        {
          freeNeighbors[freeCount++] = n;
        }
      }
      if (freeCount == 1 || freeCount == 3 || t == seed)
      {
        // One free neighbour; or a seed (three free neighbours in the paper's first patch; a
        // later seed next to a finished patch has one or two): add each feasible one. Treating
        // a two-neighbour seed like the paper's case 2 would leave it alone, and its rejected
        // neighbour would seed the next single-triangle patch along every crease.
        bool ok[3];
        for (int i = 0; i < freeCount; ++i)
        {
          ok[i] = feasible(t, freeNeighbors[i]);
        }
        for (int i = 0; i < freeCount; ++i)
        {
          if (ok[i] && this->TrianglePatch[freeNeighbors[i]] == InvalidIndex)
          {
            add(freeNeighbors[i]);
          }
          else
          {
            rejected.push_back(freeNeighbors[i]);
          }
        }
      }
      else if (freeCount == 2)
      {
        if (feasible(t, freeNeighbors[0]) && feasible(t, freeNeighbors[1]))
        {
          add(freeNeighbors[0]);
          add(freeNeighbors[1]);
        }
        else
        {
          rejected.push_back(freeNeighbors[0]);
          rejected.push_back(freeNeighbors[1]);
          // Both or neither: drop T itself to keep the patch fat, when that keeps it a disk.
          Index opposite = InvalidIndex;
          if (t != seed && sharedEdges(t, opposite) == 1 && vertexCount[opposite] == 1)
          {
            remove(t);
            rejected.push_back(t);
          }
        }
      }
    }
    this->PatchAreaVector.push_back(sum);
    this->PatchAreaOf.push_back(area);
    this->PatchTriangleCountOf.push_back(count);

    if (progress && assigned >= nextReport)
    {
      nextReport = assigned + 65536;
      if (progress(0.9 * double(assigned) / double(nt)))
      {
        this->WasAborted = true;
        return;
      }
    }
    // Next seed: a free triangle next to the patch just finished, else an older candidate, else
    // the next free triangle in index order (a new component).
    seed = InvalidIndex;
    for (const Index t : rejected)
    {
      if (this->TrianglePatch[t] == InvalidIndex)
      {
        if (seed == InvalidIndex)
        {
          seed = t;
        }
        else
        {
          candidates.push_back(t);
        }
      }
    }
    while (seed == InvalidIndex && !candidates.empty())
    {
      const Index t = candidates.back();
      candidates.pop_back();
      if (this->TrianglePatch[t] == InvalidIndex)
      {
        seed = t;
      }
    }
    while (seed == InvalidIndex && scan < nt)
    {
      if (this->TrianglePatch[scan] == InvalidIndex)
      {
        seed = scan;
      }
      ++scan;
    }
  }
}

// Chains: boundary half-edges of each patch (edges whose other side is another patch, the border
// or a non-manifold edge) are followed counter-clockwise around the patch; a chain ends where the
// patch on the other side changes. Closed loops without such a vertex (e.g. a patch inside a
// single other patch's hole... on a sphere cut in two) are cut into three chains.
void Patchification::ExtractChains(
  const TriangleMesh& mesh, const MeshTopology& topology, const Adjacency& adjacency)
{
  const Index nt = mesh.NumberOfTriangles();
  const Index nv = mesh.NumberOfPoints();
  const std::vector<Index>& patchOf = this->TrianglePatch;

  auto isBoundary = [&](Index h) {
    const Index n = adjacency.Neighbor(h / 3, h % 3);
    return n == InvalidIndex || patchOf[n] != patchOf[h / 3];
  };
  auto rightOf = [&](Index h) {
    const Index n = adjacency.Neighbor(h / 3, h % 3);
    return n == InvalidIndex ? InvalidIndex : patchOf[n];
  };
  auto nonManifold = [&](Index h) { return topology.IsNonManifoldEdge(topology.TriangleEdge(h / 3, h % 3)); };
  auto origin = [&](Index h) { return mesh.Triangles[size_t(h)]; };
  auto target = [&](Index h) { return mesh.Triangles[size_t(h - h % 3 + (h % 3 + 1) % 3)]; };
  // Next boundary half-edge of the same patch, leaving the target of h (rotate inside the patch).
  auto next = [&](Index h) {
    const Index b = target(h);
    Index g = h - h % 3 + (h % 3 + 1) % 3;
    for (Index guard = topology.VertexDegree(b) + 1; guard > 0; --guard)
    {
      if (isBoundary(g))
      {
        return g;
      }
      const Index n = adjacency.Neighbor(g / 3, g % 3);
      const Index* tri = mesh.Triangle(n);
      const int j = tri[0] == b ? 0 : (tri[1] == b ? 1 : 2);
      g = 3 * n + j;
    }
    return InvalidIndex; // not a fan (cannot happen for a disk patch of an oriented mesh)
  };

  // Endpoints: where the patch across changes along a patch boundary, plus non-manifold vertices.
  std::vector<unsigned char> isEnd(size_t(nv), 0);
  for (Index v = 0; v < nv; ++v)
  {
    if (topology.IsNonManifoldVertex(v))
    {
      isEnd[v] = 1;
    }
  }
  const Index nh = 3 * nt;
  for (Index h = 0; h < nh; ++h)
  {
    if (!isBoundary(h))
    {
      continue;
    }
    const Index g = next(h);
    if (g == InvalidIndex || rightOf(g) != rightOf(h) || nonManifold(g) != nonManifold(h))
    {
      isEnd[target(h)] = 1;
    }
  }

  this->ChainOffsets.assign(1, 0);
  this->ChainVertexList.clear();
  this->ChainLeft.clear();
  this->ChainRight.clear();
  this->ChainFlags.clear();
  std::vector<unsigned char> visited(size_t(nh), 0);
  auto owns = [&](Index h) {
    // Each two-sided chain is emitted once, from its lower patch.
    const Index r = rightOf(h);
    return r == InvalidIndex || patchOf[h / 3] < r;
  };
  auto emit = [&](Index left, Index right, bool nm) {
    this->ChainOffsets.push_back(static_cast<Index>(this->ChainVertexList.size()));
    this->ChainLeft.push_back(left);
    this->ChainRight.push_back(right);
    this->ChainFlags.push_back(nm ? NonManifoldChain : 0);
  };
  for (Index h0 = 0; h0 < nh; ++h0)
  {
    if (visited[h0] || !isEnd[origin(h0)] || !isBoundary(h0) || !owns(h0))
    {
      continue;
    }
    const Index left = patchOf[h0 / 3], right = rightOf(h0);
    const bool nm = nonManifold(h0);
    this->ChainVertexList.push_back(origin(h0));
    Index h = h0;
    while (h != InvalidIndex && !visited[h])
    {
      visited[h] = 1;
      const Index b = target(h);
      this->ChainVertexList.push_back(b);
      if (isEnd[b])
      {
        break;
      }
      h = next(h);
    }
    emit(left, right, nm);
  }
  // Closed loops without endpoints: cut at three vertices.
  std::vector<Index> loop;
  for (Index h0 = 0; h0 < nh; ++h0)
  {
    if (visited[h0] || !isBoundary(h0) || !owns(h0))
    {
      continue;
    }
    loop.clear();
    Index h = h0;
    while (h != InvalidIndex && !visited[h])
    {
      visited[h] = 1;
      loop.push_back(origin(h));
      h = next(h);
    }
    const Index left = patchOf[h0 / 3], right = rightOf(h0);
    const bool nm = nonManifold(h0);
    const size_t n = loop.size();
    const size_t cut[4] = { 0, n / 3, (2 * n) / 3, n };
    for (int part = 0; part < 3; ++part)
    {
      if (cut[part + 1] == cut[part])
      {
        continue;
      }
      isEnd[loop[cut[part]]] = 1;
      for (size_t i = cut[part]; i <= cut[part + 1]; ++i)
      {
        this->ChainVertexList.push_back(loop[i % n]);
      }
      emit(left, right, nm);
    }
  }

  // Endpoint ids.
  std::vector<Index> endpointOf(size_t(nv), InvalidIndex);
  this->EndpointVertices.clear();
  this->EndpointBorder.clear();
  const Index nc = this->NumberOfChains();
  this->ChainEndpoints.resize(2 * size_t(nc));
  for (Index c = 0; c < nc; ++c)
  {
    for (int end = 0; end < 2; ++end)
    {
      const Index v = end == 0 ? this->ChainVertexList[this->ChainOffsets[c]]
                               : this->ChainVertexList[this->ChainOffsets[c + 1] - 1];
      if (endpointOf[v] == InvalidIndex)
      {
        endpointOf[v] = static_cast<Index>(this->EndpointVertices.size());
        this->EndpointVertices.push_back(v);
        this->EndpointBorder.push_back(topology.IsBoundaryVertex(v) || topology.IsNonManifoldVertex(v));
      }
      this->ChainEndpoints[2 * size_t(c) + end] = endpointOf[v];
    }
  }

  // Patch graph (CSR): the chains around each patch.
  const Index np = this->NumberOfPatches();
  this->PatchChainOffsets.assign(size_t(np) + 1, 0);
  for (Index c = 0; c < nc; ++c)
  {
    ++this->PatchChainOffsets[this->ChainLeft[c] + 1];
    if (this->ChainRight[c] != InvalidIndex)
    {
      ++this->PatchChainOffsets[this->ChainRight[c] + 1];
    }
  }
  for (Index p = 0; p < np; ++p)
  {
    this->PatchChainOffsets[p + 1] += this->PatchChainOffsets[p];
  }
  this->PatchChainList.resize(this->PatchChainOffsets[np]);
  std::vector<Index> fill(this->PatchChainOffsets.begin(), this->PatchChainOffsets.end() - 1);
  for (Index c = 0; c < nc; ++c)
  {
    this->PatchChainList[fill[this->ChainLeft[c]]++] = c;
    if (this->ChainRight[c] != InvalidIndex)
    {
      this->PatchChainList[fill[this->ChainRight[c]]++] = c;
    }
  }
}

bool Patchification::PatchBoundaryLoop(Index p, std::vector<Index>& loop) const
{
  loop.clear();
  struct Oriented
  {
    Index Chain;
    bool Reversed;
  };
  std::vector<Oriented> chains;
  for (const Index* c = this->PatchChainsBegin(p); c != this->PatchChainsEnd(p); ++c)
  {
    if (this->ChainLeft[*c] == p)
    {
      chains.push_back({ *c, false });
    }
    if (this->ChainRight[*c] == p)
    {
      chains.push_back({ *c, true });
    }
  }
  if (chains.empty())
  {
    return false;
  }
  auto first = [&](const Oriented& o) { return o.Reversed ? this->ChainEnd(o.Chain) : this->ChainStart(o.Chain); };
  auto last = [&](const Oriented& o) { return o.Reversed ? this->ChainStart(o.Chain) : this->ChainEnd(o.Chain); };
  std::vector<char> used(chains.size(), 0);
  size_t current = 0;
  used[0] = 1;
  for (size_t step = 0; step < chains.size(); ++step)
  {
    const Oriented& o = chains[current];
    const Index* v = this->ChainVerticesBegin(o.Chain);
    const Index n = this->ChainSize(o.Chain);
    for (Index i = 0; i + 1 < n; ++i) // the last vertex starts the next chain
    {
      loop.push_back(o.Reversed ? v[n - 1 - i] : v[i]);
    }
    if (step + 1 == chains.size())
    {
      if (last(o) != first(chains[0]))
      {
        return false; // does not close
      }
      break;
    }
    size_t following = chains.size();
    for (size_t j = 0; j < chains.size(); ++j)
    {
      if (!used[j] && first(chains[j]) == last(o))
      {
        if (following != chains.size())
        {
          return false; // two ways on: not a simple loop
        }
        following = j;
      }
    }
    if (following == chains.size())
    {
      return false;
    }
    used[following] = 1;
    current = following;
  }
  // Simple: no vertex twice.
  std::vector<Index> sorted(loop);
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end() && loop.size() >= 3;
}

size_t Patchification::MemoryUsage() const
{
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(this->TrianglePatch) + bytes(this->PatchAreaVector) + bytes(this->PatchAreaOf) +
    bytes(this->PatchTriangleCountOf) + bytes(this->ChainOffsets) + bytes(this->ChainVertexList) +
    bytes(this->ChainLeft) + bytes(this->ChainRight) + bytes(this->ChainEndpoints) + bytes(this->ChainFlags) +
    bytes(this->EndpointVertices) + bytes(this->EndpointBorder) + bytes(this->PatchChainOffsets) +
    bytes(this->PatchChainList);
}
} // namespace slod
