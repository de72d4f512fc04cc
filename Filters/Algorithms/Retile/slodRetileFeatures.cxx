// SPDX-License-Identifier: BSD-3-Clause
#include "slodRetileFeatures.h"

#include "slodMeshTopology.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace slod
{
namespace
{

// A maximal run of feature edges between two corners (or a closed loop: first == last vertex).
struct Chain
{
  std::vector<Index> Vertices;
  double Length = 0;
  bool Dangling = false; // an end has a single feature edge
  bool Loop = false;
};

// Border edges and edges whose two triangles' normals differ by more than the feature angle
// (non-manifold edges are left out: their vertices are kept anyway).
std::vector<std::vector<Index>> FeatureEdgeGraph(const TriangleMesh& mesh, const MeshTopology& topology, double featureAngle)
{
  const double cosine = std::cos(Radians(featureAngle));
  std::vector<std::vector<Index>> neighbors(size_t(mesh.NumberOfPoints()));
  for (Index e = 0; e < topology.NumberOfEdges(); ++e)
  {
    const Index count = topology.EdgeTriangleCount(e);
    bool feature = count == 1;
    if (count == 2)
    {
      const Index* t = topology.EdgeTrianglesBegin(e);
      const Vec3 n0 = Normalized(mesh.TriangleAreaVector(t[0])), n1 = Normalized(mesh.TriangleAreaVector(t[1]));
      feature = Dot(n0, n1) < cosine;
    }
    if (feature)
    {
      const Index u = topology.EdgeVertex(e, 0), w = topology.EdgeVertex(e, 1);
      neighbors[u].push_back(w);
      neighbors[w].push_back(u);
    }
  }
  return neighbors;
}

// Corners: line ends, junctions of three or more lines, and sharp turns of a line.
unsigned char IsCorner(const TriangleMesh& mesh, const std::vector<std::vector<Index>>& neighbors, Index v, double cosine)
{
  const size_t degree = neighbors[v].size();
  if (degree != 2)
  {
    return degree > 0 ? 1 : 0;
  }
  const Vec3 p = mesh.Point(v);
  const Vec3 in = Normalized(p - mesh.Point(neighbors[v][0])), out = Normalized(mesh.Point(neighbors[v][1]) - p);
  return Dot(in, out) < cosine ? 1 : 0;
}

std::vector<unsigned char> CornerFlags(
  const TriangleMesh& mesh, const std::vector<std::vector<Index>>& neighbors, double featureAngle)
{
  const double cosine = std::cos(Radians(featureAngle));
  std::vector<unsigned char> corner(neighbors.size(), 0);
  for (size_t v = 0; v < neighbors.size(); ++v)
  {
    corner[v] = IsCorner(mesh, neighbors, Index(v), cosine);
  }
  return corner;
}

// Walks from vertex `from` along its neighbour `next` until a corner or back to the start.
Chain Walk(const TriangleMesh& mesh, const std::vector<std::vector<Index>>& neighbors,
  const std::vector<unsigned char>& corner, Index from, Index next, std::vector<unsigned char>& visited,
  Index& steps)
{
  Chain chain;
  chain.Vertices.push_back(from);
  Index previous = from, current = next;
  // Bounded by the vertex count: each step enters a vertex of degree 2 not yet visited.
  for (size_t guard = 0; guard <= neighbors.size(); ++guard)
  {
    chain.Length += Norm(mesh.Point(current) - mesh.Point(previous));
    chain.Vertices.push_back(current);
    ++steps;
    if (corner[current] || current == from || visited[current])
    {
      break;
    }
    visited[current] = 1;
    const Index following = neighbors[current][0] == previous ? neighbors[current][1] : neighbors[current][0];
    previous = current;
    current = following;
  }
  chain.Loop = chain.Vertices.front() == chain.Vertices.back();
  chain.Dangling = neighbors[chain.Vertices.front()].size() == 1 || neighbors[chain.Vertices.back()].size() == 1;
  return chain;
}

std::vector<Chain> Chains(const TriangleMesh& mesh, const std::vector<std::vector<Index>>& neighbors,
  const std::vector<unsigned char>& corner, Index& steps)
{
  std::vector<Chain> chains;
  std::vector<unsigned char> visited(neighbors.size(), 0);
  for (size_t v = 0; v < neighbors.size(); ++v)
  {
    for (size_t k = 0; corner[v] && k < neighbors[v].size(); ++k)
    {
      const Index w = neighbors[v][k];
      // Each chain once: from its smaller end (the corners are taken in index order), or from its
      // one corner's first line neighbour for a loop through a single corner. Seen from its other
      // end, a chain of one edge has a smaller corner there, a longer one an inner vertex already
      // walked (listing that edge as a chain of its own made a dangling line whose free end has
      // the larger index lose one edge per pruning round: Documentation/Retile.md, session 22).
      if ((corner[w] && w < Index(v)) || (!corner[w] && visited[w] == 2))
      {
        continue;
      }
      Chain chain = Walk(mesh, neighbors, corner, Index(v), w, visited, steps);
      for (size_t i = 1; i + 1 < chain.Vertices.size(); ++i)
      {
        visited[chain.Vertices[i]] = 2;
      }
      chains.push_back(std::move(chain));
    }
  }
  for (size_t v = 0; v < neighbors.size(); ++v)
  {
    if (!corner[v] && neighbors[v].size() == 2 && !visited[v])
    {
      // A loop without corners: starts anywhere.
      visited[v] = 2;
      Chain chain = Walk(mesh, neighbors, corner, Index(v), neighbors[v][0], visited, steps);
      for (Index u : chain.Vertices)
      {
        visited[u] = 2;
      }
      chains.push_back(std::move(chain));
    }
  }
  return chains;
}

// Noise a re-tiling at this spacing cannot show: a line shorter than the spacing that ends freely,
// or a loop shorter than three spacings.
bool IsNoise(const Chain& chain, double spacing)
{
  return (chain.Dangling && chain.Length < spacing) || (chain.Loop && chain.Length < 3 * spacing);
}

// The chains of the present lines through the vertices whose feature edges changed (the ends of
// the chains just dropped), each once (found from several of them, a chain is the same edges).
// Only they can have become noise: every other chain has the same vertices, corners and ends as
// before the drop, when it was not noise.
std::vector<Chain> ChainsThrough(const TriangleMesh& mesh, const std::vector<std::vector<Index>>& neighbors,
  const std::vector<unsigned char>& corner, const std::vector<Index>& changed, std::vector<unsigned char>& visited,
  Index& steps)
{
  std::vector<std::pair<std::pair<Index, Index>, Chain>> found;
  auto walk = [&](Index from, Index next) {
    Chain chain = Walk(mesh, neighbors, corner, from, next, visited, steps);
    // A vertex that is not a corner belongs to one chain only (its smallest names the chain,
    // whichever vertex the walk started from); a chain without one is its single edge.
    const Index a = chain.Vertices.front(), b = chain.Vertices.back();
    std::pair<Index, Index> key{ std::min(a, b), std::max(a, b) };
    for (Index v : chain.Vertices)
    {
      visited[v] = 0;
      key = corner[v] ? key : std::min(key, std::pair<Index, Index>{ -1, v });
    }
    found.emplace_back(key, std::move(chain));
  };
  for (Index d : changed)
  {
    if (neighbors[d].empty())
    {
      continue;
    }
    if (corner[d])
    {
      for (Index w : neighbors[d])
      {
        walk(d, w);
      }
      continue;
    }
    // Inside a line: go to a corner, then walk the chain from there (or round a loop without one).
    Index previous = d, current = neighbors[d][0];
    for (size_t guard = 0; guard <= neighbors.size() && !corner[current] && current != d; ++guard)
    {
      const Index following = neighbors[current][0] == previous ? neighbors[current][1] : neighbors[current][0];
      previous = current;
      current = following;
      ++steps;
    }
    current == d ? walk(d, neighbors[d][0]) : walk(current, previous);
  }
  std::stable_sort(found.begin(), found.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<Chain> chains;
  for (size_t i = 0; i < found.size(); ++i)
  {
    if (i == 0 || found[i].first != found[i - 1].first)
    {
      chains.push_back(std::move(found[i].second));
    }
  }
  return chains;
}

void RemoveChainEdges(const Chain& chain, std::vector<std::vector<Index>>& neighbors)
{
  for (size_t i = 0; i + 1 < chain.Vertices.size(); ++i)
  {
    const Index u = chain.Vertices[i], w = chain.Vertices[i + 1];
    auto& nu = neighbors[u];
    auto& nw = neighbors[w];
    nu.erase(std::remove(nu.begin(), nu.end(), w), nu.end());
    nw.erase(std::remove(nw.begin(), nw.end(), u), nw.end());
  }
}

// Points at the spacing between the kept chain positions i0 < i1 when they are 1.5 spacings or more
// apart along the chain (FeatureLines::GapPoints).
void GapPointsBetween(const Chain& chain, const std::vector<double>& arc, size_t i0, size_t i1, double spacing,
  std::vector<LinePoint>& gaps)
{
  const double start = arc[i0], length = arc[i1] - start;
  if (length < 1.5 * spacing)
  {
    return;
  }
  const long long pieces = std::llround(length / spacing);
  size_t i = i0;
  for (long long j = 1; j < pieces; ++j) // bounded: pieces < length / spacing + 1
  {
    const double s = start + length * double(j) / double(pieces);
    while (i + 1 < i1 && arc[i + 1] < s)
    {
      ++i;
    }
    const double edge = arc[i + 1] - arc[i];
    gaps.push_back(LinePoint{ chain.Vertices[i], chain.Vertices[i + 1], edge > 0 ? (s - arc[i]) / edge : 0.0 });
  }
}

// Interior samples of a chain at even arc-length steps near `spacing`, snapped to its vertices;
// and the gap points between the kept vertices (its ends and the samples).
void SampleChain(const TriangleMesh& mesh, const Chain& chain, double spacing, std::vector<Index>& kept,
  std::vector<LinePoint>& gaps)
{
  const size_t m = chain.Vertices.size();
  std::vector<double> arc(m, 0.0);
  for (size_t i = 1; i < m; ++i)
  {
    arc[i] = arc[i - 1] + Norm(mesh.Point(chain.Vertices[i]) - mesh.Point(chain.Vertices[i - 1]));
  }
  // A loop without corners keeps its start as a sample (at least three, so it stays a loop).
  const long long pieces = std::max<long long>(chain.Loop ? 3 : 1, std::llround(chain.Length / spacing));
  size_t last = 0;
  for (long long j = 1; j < pieces; ++j)
  {
    const double s = chain.Length * double(j) / double(pieces);
    size_t i = size_t(std::lower_bound(arc.begin(), arc.end(), s) - arc.begin());
    if (i > 0 && (i == m || s - arc[i - 1] < arc[i] - s))
    {
      --i;
    }
    if (i > last && i + 1 < m)
    {
      kept.push_back(chain.Vertices[i]);
      GapPointsBetween(chain, arc, last, i, spacing, gaps);
      last = i;
    }
  }
  GapPointsBetween(chain, arc, last, m - 1, spacing, gaps);
}
} // namespace

double EvenSpacing(double area, Index count)
{
  return count > 0 ? std::sqrt(2.0 * area / (std::sqrt(3.0) * double(count))) : 0.0;
}

namespace
{
// The triangles of each gap point's edge, from the topology the lines came from (a gap point's
// edge is a feature edge: one or two triangles).
void FindGapPointFaces(const MeshTopology& topology, std::vector<LinePoint>& gaps)
{
  for (LinePoint& g : gaps)
  {
    const Index e = topology.FindEdge(g.From, g.To);
    const Index count = e == InvalidIndex ? 0 : std::min<Index>(2, topology.EdgeTriangleCount(e));
    for (Index k = 0; k < count; ++k)
    {
      g.Faces[k] = topology.EdgeTrianglesBegin(e)[k];
    }
  }
}

// The lines of the feature edge graph `neighbors` (moved into features.LineNeighbors).
void LinesOfGraph(const TriangleMesh& mesh, const MeshTopology& topology, std::vector<std::vector<Index>> neighbors,
  double featureAngle, double spacing, FeatureLines& features)
{
  features = FeatureLines();
  const double cosine = std::cos(Radians(featureAngle));
  std::vector<unsigned char> corner = CornerFlags(mesh, neighbors, featureAngle);
  std::vector<Chain> chains = Chains(mesh, neighbors, corner, features.WalkSteps);
  // Noise chains are dropped, which may make other short dangling chains (bounded rounds). After
  // the first round only the chains through the dropped chains' ends are walked again: walking
  // every line each round made this stage grow faster than the input (noisy scans drop chains
  // for several rounds, more on larger ones).
  std::vector<Index> changed;
  std::vector<unsigned char> visited(neighbors.size(), 0);
  bool pruned = false;
  for (int round = 0; round < 16; ++round)
  {
    changed.clear();
    for (const Chain& chain : chains)
    {
      if (IsNoise(chain, spacing))
      {
        RemoveChainEdges(chain, neighbors);
        changed.push_back(chain.Vertices.front());
        changed.push_back(chain.Vertices.back());
      }
    }
    features.DroppedChains += Index(changed.size() / 2);
    if (changed.empty())
    {
      break;
    }
    pruned = true;
    ++features.PruningRounds;
    for (Index v : changed)
    {
      corner[v] = IsCorner(mesh, neighbors, v, cosine);
    }
    chains = ChainsThrough(mesh, neighbors, corner, changed, visited, features.WalkSteps);
  }
  // The lines in their usual order (corners by index), for the samples.
  if (pruned)
  {
    chains = Chains(mesh, neighbors, corner, features.WalkSteps);
  }
  for (size_t v = 0; v < neighbors.size(); ++v)
  {
    features.FeatureEdges += Index(neighbors[v].size());
    if (corner[v])
    {
      features.Kept.push_back(Index(v));
    }
  }
  features.FeatureEdges /= 2;
  features.Corners = Index(features.Kept.size());
  for (const Chain& chain : chains)
  {
    if (chain.Loop && !corner[chain.Vertices.front()])
    {
      features.Kept.push_back(chain.Vertices.front()); // a loop without corners: its start
    }
    SampleChain(mesh, chain, spacing, features.Kept, features.GapPoints);
  }
  FindGapPointFaces(topology, features.GapPoints);
  features.LineNeighbors = std::move(neighbors);
}
} // namespace

void DetectFeatureLines(const TriangleMesh& mesh, double featureAngle, double spacing, FeatureLines& features)
{
  const MeshTopology topology(mesh);
  DetectFeatureLines(mesh, topology, featureAngle, spacing, features);
}

void DetectFeatureLines(const TriangleMesh& mesh, const MeshTopology& topology, double featureAngle, double spacing,
  FeatureLines& features)
{
  LinesOfGraph(mesh, topology, FeatureEdgeGraph(mesh, topology, featureAngle), featureAngle, spacing, features);
}
} // namespace slod
