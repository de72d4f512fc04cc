// SPDX-License-Identifier: BSD-3-Clause
#include "slodEditableMesh.h"

#include "slodGroupByKey.h"
#include "slodHugePages.h"

#include <algorithm>
#include <cassert>
#include <limits>

namespace slod
{
const char* ToString(CollapseStatus status)
{
  switch (status)
  {
    case CollapseStatus::Ok: return "ok";
    case CollapseStatus::DeadVertex: return "dead vertex";
    case CollapseStatus::NonManifold: return "non-manifold result";
    case CollapseStatus::BoundaryChange: return "boundary change";
    case CollapseStatus::TooSmall: return "component too small";
    case CollapseStatus::Flip: return "triangle flip";
    case CollapseStatus::Degenerate: return "degenerate triangle";
    case CollapseStatus::BadShape: return "bad triangle shape";
    case CollapseStatus::IsolatedVertex: return "a vertex would lose all its triangles";
    case CollapseStatus::Locked: return "locked vertex";
  }
  return "unknown";
}

void EditableMesh::Reset(const TriangleMesh& mesh)
{
  CopyOnHugePages(this->Points, mesh.Points);
  CopyOnHugePages(this->Triangles, mesh.Triangles);
  const Index np = this->NumberOfPoints();
  const Index nt = this->NumberOfTriangles();
  this->TriangleAlive.assign(nt, 1);
  this->VertexAlive.assign(np, 1);
  this->LiveTriangles = nt;
  this->LiveVertices = np;
  if (this->VertexLinkMarks)
  {
    AssignOnHugePages(this->VertexLink, size_t(np), LinkEntry());
  }
  else
  {
    std::vector<LinkEntry>().swap(this->VertexLink);
  }
  this->Epoch = 0;
  AssignOnHugePages(this->RefStart, size_t(np), Index(0));
  AssignOnHugePages(this->RefCount, size_t(np), Index(0));
  this->Refs.clear();
  this->CompactThreshold = 0;
  this->RebuildThreshold = 0;
  this->CompactedAway = 0;
  this->RoomLimit = 0;
  this->Refs.push_back(0); // forces the first build of the blocks
  this->CompactIfNeeded();
}

std::uint32_t EditableMesh::NextEpoch() const
{
  // Atomic: concurrent checks (see CheckCollapse with a scratch) each need their own epoch. The
  // wrap-around clears the marks, which only a sequential caller may do (ReserveEpochs).
  const std::uint32_t epoch = __atomic_add_fetch(&this->Epoch, 1u, __ATOMIC_RELAXED);
  if (epoch == 0)
  {
    this->ClearMarks();
    return this->Epoch;
  }
  return epoch;
}

void EditableMesh::ClearMarks() const
{
  for (LinkEntry& e : this->VertexLink)
  {
    e.Mark = 0;
  }
  this->Epoch = 1;
}

void EditableMesh::ReserveEpochs(std::uint32_t checks) const
{
  // A check takes at most two epochs (the link test and IsBoundaryVertex); margin for Neighbors.
  if (this->Epoch > std::numeric_limits<std::uint32_t>::max() - 4 * checks - 16)
  {
    this->ClearMarks();
  }
}

void EditableMesh::SetPoint(Index v, const Vec3& p)
{
  std::copy(p.begin(), p.end(), &this->Points[3 * size_t(v)]);
}

Vec3 EditableMesh::TriangleNormal(Index t) const
{
  const Index* tri = this->Triangle(t);
  return slod::TriangleNormal(this->Point(tri[0]), this->Point(tri[1]), this->Point(tri[2]));
}

double EditableMesh::TriangleArea(Index t) const
{
  const Index* tri = this->Triangle(t);
  const Vec3 a = this->Point(tri[0]);
  return 0.5 * Norm(Cross(this->Point(tri[1]) - a, this->Point(tri[2]) - a));
}

Index EditableMesh::VertexDegree(Index v) const
{
  Index n = 0;
  this->ForEachTriangle(v, [&](Index) { ++n; });
  return n;
}

int EditableMesh::EdgeTriangleCount(Index u, Index v) const
{
  int n = 0;
  this->ForEachTriangle(u, [&](Index t) {
    const Index* tri = this->Triangle(t);
    n += (tri[0] == v || tri[1] == v || tri[2] == v) ? 1 : 0;
  });
  return n;
}

void EditableMesh::GatherTriangles(const Index* vertices, int count, std::vector<Index>& gathered) const
{
  // A triangle around vertices[i] was gathered already when it holds an earlier vertex of the set
  // (no per-triangle mark array: one random access fewer per triangle, 4 bytes per triangle less).
  // A triangle with a repeated vertex is listed once per corner in that vertex's block.
  gathered.clear();
  for (int i = 0; i < count; ++i)
  {
    const Index v = vertices[i];
    this->ForEachTriangle(v, [&](Index t) {
      const Index* tri = this->Triangle(t);
      for (int j = 0; j < i; ++j)
      {
        if (tri[0] == vertices[j] || tri[1] == vertices[j] || tri[2] == vertices[j])
        {
          return;
        }
      }
      if (int(tri[0] == v) + int(tri[1] == v) + int(tri[2] == v) > 1 &&
        std::find(gathered.begin(), gathered.end(), t) != gathered.end())
      {
        return;
      }
      gathered.push_back(t);
    });
  }
}

void EditableMesh::TrianglesAround(const Index* vertices, int count, std::vector<Index>& out) const
{
  this->GatherTriangles(vertices, count, this->Scratch);
  out.assign(this->Scratch.begin(), this->Scratch.end());
}

namespace
{
// The corner after k around a triangle (a table: (k + 1) % 3 cost a multiply per use in the hot checks).
constexpr int NextCorner[3] = { 1, 2, 0 };

// How many of the triangle's corners are in the set (each match counted), and the last such corner.
template <int Count>
inline int CountMembersOf(const Index* tri, const Index* set, int& corner)
{
  int members = 0;
  for (int k = 0; k < 3; ++k)
  {
    int matches = 0;
    for (int i = 0; i < Count; ++i)
    {
      matches += tri[k] == set[i] ? 1 : 0;
    }
    members += matches;
    corner = matches > 0 ? k : corner;
  }
  return members;
}

// Called for every gathered triangle of every check and collapse: the sets of edge and triangle
// collapses (two and three vertices) get unrolled compares without branches (the loop over a
// runtime count cost about 70 instructions per call, session 38).
inline int CountMembers(const Index* tri, const Index* set, int count, int& corner)
{
  if (count == 2)
  {
    return CountMembersOf<2>(tri, set, corner);
  }
  if (count == 3)
  {
    return CountMembersOf<3>(tri, set, corner);
  }
  int members = 0;
  for (int k = 0; k < 3; ++k)
  {
    for (int i = 0; i < count; ++i)
    {
      if (tri[k] == set[i])
      {
        ++members;
        corner = k;
      }
    }
  }
  return members;
}
} // namespace

void EditableMesh::PrefetchGathered(const std::vector<Index>& gathered) const
{
  // The checks read every gathered triangle's corners, their link scratch and points: prefetch
  // them all first so that the misses overlap (the check is bound by memory latency).
  for (Index t : gathered)
  {
    __builtin_prefetch(this->Triangle(t));
  }
  for (Index t : gathered)
  {
    const Index* tri = this->Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      if (this->VertexLinkMarks)
      {
        __builtin_prefetch(&this->VertexLink[tri[k]]);
      }
      __builtin_prefetch(&this->Points[3 * size_t(tri[k])]);
    }
  }
}

// A touched vertex's link edges in a link test's marks: the neighbour before it (In) and after it
// (Out), InvalidIndex while none.
namespace
{
struct LinkSlot
{
  Index& In;
  Index& Out;
};
} // namespace

// The link test's marks per vertex: In and Out, unset until the vertex is touched in this check.
struct EditableMesh::MarkedLink
{
  std::vector<LinkEntry>& Entries;
  const std::uint32_t Epoch;
  void Touch(Index w)
  {
    LinkEntry& e = this->Entries[w];
    if (e.Mark != this->Epoch)
    {
      e.Mark = this->Epoch;
      e.In = InvalidIndex;
      e.Out = InvalidIndex;
    }
  }
  bool Touched(Index w) const { return this->Entries[w].Mark == this->Epoch; }
  Index& In(Index w) { return this->Entries[w].In; }
  Index& Out(Index w) { return this->Entries[w].Out; }
  // Touch(w), then w's In and Out (see LinkSlot).
  LinkSlot At(Index w)
  {
    this->Touch(w);
    LinkEntry& e = this->Entries[w];
    return { e.In, e.Out };
  }
};

// The same in the caller's table: open addressing, at most half full (a check touches at most two
// vertices per gathered triangle), cleared per check (its size, not the mesh's).
struct EditableMesh::TableLink
{
  CheckScratch& Scratch;
  size_t Mask;
  TableLink(CheckScratch& scratch, size_t gathered)
    : Scratch(scratch)
  {
    size_t size = 16;
    while (size < 4 * gathered)
    {
      size *= 2;
    }
    this->Mask = size - 1;
    scratch.Keys.assign(size, InvalidIndex);
    scratch.Links.resize(size);
  }
  size_t Slot(Index w) const
  {
    size_t h = (size_t(std::uint32_t(w)) * 0x9E3779B1u) & this->Mask;
    while (this->Scratch.Keys[h] != w && this->Scratch.Keys[h] != InvalidIndex) // (never full)
    {
      h = (h + 1) & this->Mask;
    }
    return h;
  }
  void Touch(Index w)
  {
    const size_t h = this->Slot(w);
    if (this->Scratch.Keys[h] == InvalidIndex)
    {
      this->Scratch.Keys[h] = w;
      this->Scratch.Links[h] = { InvalidIndex, InvalidIndex };
    }
  }
  bool Touched(Index w) const { return this->Scratch.Keys[this->Slot(w)] == w; }
  Index& In(Index w) { return this->Scratch.Links[this->Slot(w)][0]; }
  Index& Out(Index w) { return this->Scratch.Links[this->Slot(w)][1]; }
  // Touch(w), then w's In and Out: one probe of the table where Touch, In and Out made one each
  // (CheckLink's scan made eight per surviving triangle: 1,190 instructions per check on noisy137,
  // session 44). A slot never moves while the table lives (no removal, no growth).
  LinkSlot At(Index w)
  {
    const size_t h = this->Slot(w);
    if (this->Scratch.Keys[h] == InvalidIndex)
    {
      this->Scratch.Keys[h] = w;
      this->Scratch.Links[h] = { InvalidIndex, InvalidIndex };
    }
    return { this->Scratch.Links[h][0], this->Scratch.Links[h][1] };
  }
};

// Around v each triangle (v, x, y) contributes the link edge x -> y; an edge (v, x) is on the
// border exactly when x has unequal numbers of incoming and outgoing link edges. (With the marks
// off the vertices around v go to the mesh's table, sized for two per triangle of v's block.)
bool EditableMesh::IsBoundaryVertex(Index v) const
{
  return this->VertexLinkMarks ? this->BorderThrough(v, MarkedLink{ this->VertexLink, this->NextEpoch() })
                               : this->BorderThrough(v, TableLink(this->LinkTable, size_t(this->RefCount[v])));
}

void EditableMesh::BoundaryVertexFlags(std::vector<unsigned char>& flags) const
{
  // BorderThrough's In and Out per neighbour w of v are the corners after and before v in v's
  // triangles: v is on a border when some w other than v is not as often the one as the other,
  // i.e. when the two lists differ as multisets. Each corner after v is matched with an equal
  // corner before it (taken out of that list); one without a match, or one left over, is a border.
  constexpr int Capacity = 32; // (fans of more: IsBoundaryVertex)
  Index after[Capacity], before[Capacity];
  const Index np = this->NumberOfPoints();
  flags.assign(size_t(np), 0);
  for (Index v = 0; v < np; ++v)
  {
    int n = 0;
    bool fits = true;
    this->ForEachTriangle(v, [&](Index t) {
      fits = fits && n < Capacity;
      if (fits)
      {
        const Index* tri = this->Triangle(t);
        const int c = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
        after[n] = tri[NextCorner[c]];
        before[n++] = tri[NextCorner[NextCorner[c]]];
      }
    });
    if (!fits)
    {
      flags[size_t(v)] = this->IsBoundaryVertex(v) ? 1 : 0;
      continue;
    }
    bool boundary = false;
    int left = n;
    for (int i = 0; i < n && !boundary; ++i)
    {
      if (after[i] == v)
      {
        continue;
      }
      int j = 0;
      while (j < left && before[j] != after[i]) // (at most n steps)
      {
        ++j;
      }
      if (j == left)
      {
        boundary = true;
      }
      else
      {
        before[j] = before[--left];
      }
    }
    for (int j = 0; j < left && !boundary; ++j)
    {
      boundary = before[j] != v;
    }
    flags[size_t(v)] = boundary ? 1 : 0;
  }
}

template <typename Link>
bool EditableMesh::BorderThrough(Index v, Link&& link) const
{
  this->ForEachTriangle(v, [&](Index t) {
    const Index* tri = this->Triangle(t);
    const int c = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    const Index x = tri[(c + 1) % 3], y = tri[(c + 2) % 3];
    link.Touch(x);
    link.Touch(y);
    ++link.Out(x);
    ++link.In(y);
  });
  bool boundary = false;
  this->ForEachTriangle(v, [&](Index t) {
    const Index* tri = this->Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] != v && link.In(tri[k]) != link.Out(tri[k]))
      {
        boundary = true;
      }
    }
  });
  return boundary;
}

void EditableMesh::Neighbors(Index v, std::vector<Index>& out) const
{
  out.clear();
  if (this->VertexLinkMarks)
  {
    this->NeighborsThrough(v, MarkedLink{ this->VertexLink, this->NextEpoch() }, out);
  }
  else
  {
    this->NeighborsThrough(v, TableLink(this->LinkTable, size_t(this->RefCount[v])), out);
  }
}

template <typename Link>
void EditableMesh::NeighborsThrough(Index v, Link&& link, std::vector<Index>& out) const
{
  this->ForEachTriangle(v, [&](Index t) {
    const Index* tri = this->Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] != v && !link.Touched(tri[k]))
      {
        link.Touch(tri[k]);
        out.push_back(tri[k]);
      }
    }
  });
}

// What CheckLink's pass over the gathered triangles learnt, for the tests after it: the surviving
// triangles with the corner of the set's vertex (in gathered order) and the triangles holding
// exactly two of the set. Complete only when the pass went through every triangle and the lists
// held them all (a fan of more than 64 survivors); otherwise the later tests scan the gathered
// triangles and count their members again, as before (the same answers either way).
struct EditableMesh::SetScan
{
  static constexpr int SurvivorCapacity = 64, PairCapacity = 8;
  Index Survivor[SurvivorCapacity];
  unsigned char Corner[SurvivorCapacity];
  Index Pair[PairCapacity];
  int Survivors = 0, Pairs = 0;
  bool Complete = false;
};

template <typename Link>
CollapseStatus EditableMesh::CheckLink(const Index* vertices, int count, bool anyBoundary,
  const std::vector<Index>& gathered, Link&& link, SetScan& scan) const
{
  // Generalised link condition: the link of the merged vertex, made of the link edges x -> y of
  // the surviving triangles, must be one simple cycle (interior) or one simple path (border),
  // and no neighbour may get two incoming or outgoing link edges (an edge with > 2 triangles).
  // The path starts (an outgoing link edge, no incoming one) are counted as the edges arrive,
  // their ids XORed: when there is one, that is it (each vertex gets at most one edge of each
  // kind, so a start is added once and taken back once at most). Before session 30 a second pass
  // read every corner of every gathered triangle to find them.
  Index survivors = 0;
  Index firstX = InvalidIndex;
  Index starts = 0, startIds = 0;
  bool overflow = false;
  scan.Survivors = 0;
  scan.Pairs = 0;
  scan.Complete = false;
  for (Index t : gathered)
  {
    int corner = 0;
    const Index* tri = this->Triangle(t);
    const int members = CountMembers(tri, vertices, count, corner);
    if (members >= 2)
    {
      overflow = overflow || (members == 2 && scan.Pairs == SetScan::PairCapacity);
      if (members == 2 && scan.Pairs < SetScan::PairCapacity)
      {
        scan.Pair[scan.Pairs++] = t;
      }
      continue;
    }
    if (scan.Survivors < SetScan::SurvivorCapacity)
    {
      scan.Survivor[scan.Survivors] = t;
      scan.Corner[scan.Survivors++] = static_cast<unsigned char>(corner);
    }
    else
    {
      overflow = true;
    }
    const Index x = tri[NextCorner[corner]], y = tri[NextCorner[NextCorner[corner]]];
    // (x and y are the same vertex only in a triangle with a repeated corner: then lx and ly are
    // one slot, read and written in the order of the accessors this replaced.)
    const LinkSlot lx = link.At(x);
    const LinkSlot ly = link.At(y);
    if (lx.Out != InvalidIndex || ly.In != InvalidIndex)
    {
      return CollapseStatus::NonManifold;
    }
    if (lx.In == InvalidIndex)
    {
      ++starts;
      startIds ^= x;
    }
    lx.Out = y;
    if (ly.Out != InvalidIndex)
    {
      --starts;
      startIds ^= y;
    }
    ly.In = x;
    firstX = firstX == InvalidIndex ? x : firstX;
    ++survivors;
  }
  scan.Complete = !overflow;
  if (survivors == 0)
  {
    return CollapseStatus::TooSmall;
  }
  // More than one start means several fans (a pinched vertex).
  if (starts > 1)
  {
    return CollapseStatus::NonManifold;
  }
  const bool isPath = starts == 1;
  const Index start = isPath ? startIds : InvalidIndex;
  // Walk the link: it must use every surviving triangle's link edge exactly once.
  // (Every vertex walked was touched by the scan: At only reads its slot.)
  Index walked = 0;
  if (isPath)
  {
    for (Index w = start, next = link.At(w).Out; next != InvalidIndex && walked <= survivors; next = link.At(w).Out)
    {
      ++walked;
      w = next;
    }
  }
  else
  {
    Index w = firstX;
    do
    {
      w = link.At(w).Out;
      ++walked;
    } while (w != InvalidIndex && w != firstX && walked <= survivors);
  }
  if (walked != survivors)
  {
    return CollapseStatus::NonManifold;
  }
  if (isPath != anyBoundary)
  {
    return CollapseStatus::BoundaryChange;
  }
  if (!isPath && survivors < 3)
  {
    return CollapseStatus::TooSmall;
  }
  return CollapseStatus::Ok;
}

bool EditableMesh::BorderVerticesFormChain(const Index* vertices, int count, const bool* onBoundary) const
{
  // Merging two border vertices not joined along the border would close a hole or join two
  // loops, which the link of the merged vertex alone does not always reveal.
  const int borderVertices = int(onBoundary[0]) + int(onBoundary[1]) + int(onBoundary[2]);
  if (borderVertices < 2)
  {
    return true;
  }
  int borderEdges = 0;
  for (int k = 0, edges = count == 3 ? 3 : 1; k < edges; ++k)
  {
    const int j = (k + 1) % count;
    if (onBoundary[k] && onBoundary[j] && this->EdgeTriangleCount(vertices[k], vertices[j]) == 1)
    {
      ++borderEdges;
    }
  }
  return borderEdges >= borderVertices - 1;
}

bool EditableMesh::LosesAllTriangles(Index t, const Index* vertices, int count, const CollapseOptions& options) const
{
  const Index* tri = this->Triangle(t);
  auto outside = [&](Index v) { return std::find(vertices, vertices + count, v) == vertices + count; };
  const Index x = outside(tri[0]) ? tri[0] : (outside(tri[1]) ? tri[1] : tri[2]);
  if (options.BoundaryVertices && !options.BoundaryVertices[x])
  {
    // An interior vertex has a closed fan of at least three triangles; the link test already
    // rejected the only way to remove all of them (a closed tetrahedron).
    return false;
  }
  bool keepsOne = false;
  this->ForEachTriangle(x, [&](Index u) {
    int c = 0;
    keepsOne = keepsOne || CountMembers(this->Triangle(u), vertices, count, c) < 2;
  });
  return !keepsOne;
}

bool EditableMesh::IsolatesVertex(const Index* vertices, int count, const CollapseOptions& options,
  const std::vector<Index>& gathered, const SetScan& scan) const
{
  // A vertex outside the set loses all its triangles when every one of them holds two of the
  // set (a border "ear" whose base collapses): it would vanish from the mesh. The triangles that
  // hold two of the set come from the link test's scan when it is complete.
  if (scan.Complete)
  {
    for (int i = 0; i < scan.Pairs; ++i)
    {
      if (this->LosesAllTriangles(scan.Pair[i], vertices, count, options))
      {
        return true;
      }
    }
    return false;
  }
  for (Index t : gathered)
  {
    int corner = 0;
    if (CountMembers(this->Triangle(t), vertices, count, corner) == 2 &&
      this->LosesAllTriangles(t, vertices, count, options))
    {
      return true;
    }
  }
  return false;
}

namespace
{
// The geometry test of one surviving triangle (its corners) whose corner `corner` moves to p, given
// its normal, that normal's length and its minimum angle before (CheckGeometry and CheckTrial).
// newNormal: the moved triangle's area vector (for CollapseOptions::Survivors).
inline CollapseStatus MovedCornerStatus(const Vec3 (&corners)[3], int corner, const Vec3& p, const Vec3& oldNormal,
  double oldLength, double oldMinAngle, const CollapseOptions& options, Vec3& newNormal)
{
  // The moved triangle's corners by reference (no copy indexed at run time, which kept the
  // corners in memory; session 38).
  const Vec3& q0 = corner == 0 ? p : corners[0];
  const Vec3& q1 = corner == 1 ? p : corners[1];
  const Vec3& q2 = corner == 2 ? p : corners[2];
  // The new normal's length is also the degeneracy test's area (computed once).
  newNormal = Cross(q1 - q0, q2 - q0);
  const double newLength = Norm(newNormal);
  if (IsDegenerateWithArea(q0, q1, q2, newLength))
  {
    return CollapseStatus::Degenerate;
  }
  if (oldLength > 0 && Dot(oldNormal, newNormal) < options.MinimumNormalDot * oldLength * newLength)
  {
    return CollapseStatus::Flip;
  }
  if (options.MinimumAngle > 0)
  {
    const double newMinAngle = MinimumAngle(q0, q1, q2);
    if (newMinAngle < options.MinimumAngle && newMinAngle < oldMinAngle)
    {
      return CollapseStatus::BadShape;
    }
  }
  return CollapseStatus::Ok;
}
} // namespace

// Up to Capacity survivors' new area vectors, kept for TestSurvivors; more are computed again there
// (a set of more than 32 surviving triangles is rare: vertices of high valence).
struct EditableMesh::SurvivorNormals
{
  static constexpr int Capacity = 32;
  Index Triangles[Capacity];
  Vec3 Normals[Capacity];
  int Kept = 0;
  int Survivors = 0; // passed the geometry (when over Capacity, the kept ones are not used)
  bool Wanted = false;
};

CollapseStatus EditableMesh::SurvivorGeometry(
  Index t, int corner, const Vec3& p, const CollapseOptions& options, SurvivorNormals& normals) const
{
  const Index* tri = this->Triangle(t);
  const Vec3 q[3] = { this->Point(tri[0]), this->Point(tri[1]), this->Point(tri[2]) };
  const Vec3 oldNormal = Cross(q[1] - q[0], q[2] - q[0]);
  const double oldMinAngle = options.MinimumAngle > 0 ? MinimumAngle(q[0], q[1], q[2]) : 0.0;
  Vec3 newNormal;
  const CollapseStatus status = MovedCornerStatus(q, corner, p, oldNormal, Norm(oldNormal), oldMinAngle, options, newNormal);
  if (normals.Wanted && status == CollapseStatus::Ok && normals.Survivors++ < SurvivorNormals::Capacity)
  {
    normals.Triangles[normals.Kept] = t;
    normals.Normals[normals.Kept++] = newNormal;
  }
  return status;
}

// The caller's test of the survivors (options.Survivors) with their new area vectors: those kept
// by CheckGeometry, or, when they were more than it keeps, all of them computed again in chunks
// (the same expression as MovedCornerStatus: the same numbers).
CollapseStatus EditableMesh::TestSurvivors(const Index* vertices, int count, const Vec3& p,
  const CollapseOptions& options, const std::vector<Index>& gathered, const SurvivorNormals& normals) const
{
  if (!options.Survivors)
  {
    return CollapseStatus::Ok;
  }
  if (normals.Survivors <= SurvivorNormals::Capacity)
  {
    return options.Survivors->Keeps(normals.Triangles, normals.Normals, normals.Kept) ? CollapseStatus::Ok
                                                                                      : CollapseStatus::Flip;
  }
  SurvivorNormals chunk;
  for (size_t i = 0; i <= gathered.size(); ++i) // (one step past the end: the last chunk)
  {
    int corner = 0;
    if (i < gathered.size() && CountMembers(this->Triangle(gathered[i]), vertices, count, corner) < 2)
    {
      const Index* tri = this->Triangle(gathered[i]);
      const Vec3 q[3] = { this->Point(tri[0]), this->Point(tri[1]), this->Point(tri[2]) };
      const Vec3& q0 = corner == 0 ? p : q[0];
      const Vec3& q1 = corner == 1 ? p : q[1];
      const Vec3& q2 = corner == 2 ? p : q[2];
      chunk.Triangles[chunk.Kept] = gathered[i];
      chunk.Normals[chunk.Kept++] = Cross(q1 - q0, q2 - q0);
    }
    if ((chunk.Kept == SurvivorNormals::Capacity || i == gathered.size()) && chunk.Kept > 0)
    {
      if (!options.Survivors->Keeps(chunk.Triangles, chunk.Normals, chunk.Kept))
      {
        return CollapseStatus::Flip;
      }
      chunk.Kept = 0;
    }
  }
  return CollapseStatus::Ok;
}

CollapseStatus EditableMesh::CheckGeometry(const Index* vertices, int count, const Vec3& p, const CollapseOptions& options,
  const std::vector<Index>& gathered, const SetScan* scan, SurvivorNormals& normals) const
{
  // The surviving triangles with the set moved to p, in gathered order (the link test's list
  // when complete).
  if (scan && scan->Complete)
  {
    for (int i = 0; i < scan->Survivors; ++i)
    {
      const CollapseStatus status = this->SurvivorGeometry(scan->Survivor[i], scan->Corner[i], p, options, normals);
      if (status != CollapseStatus::Ok)
      {
        return status;
      }
    }
    return CollapseStatus::Ok;
  }
  for (Index t : gathered)
  {
    int corner = 0;
    if (CountMembers(this->Triangle(t), vertices, count, corner) >= 2)
    {
      continue;
    }
    const CollapseStatus status = this->SurvivorGeometry(t, corner, p, options, normals);
    if (status != CollapseStatus::Ok)
    {
      return status;
    }
  }
  return CollapseStatus::Ok;
}

CollapseStatus EditableMesh::CheckCollapse(
  const Index* vertices, int count, const Vec3& p, const CollapseOptions& options) const
{
  return this->CheckCollapse(vertices, count, p, options, this->Scratch);
}

CollapseStatus EditableMesh::CheckCollapse(const Index* vertices, int count, const Vec3& p,
  const CollapseOptions& options, std::vector<Index>& scratch) const
{
  return this->CheckCollapseWith(vertices, count, p, options, scratch, nullptr);
}

CollapseStatus EditableMesh::CheckCollapse(
  const Index* vertices, int count, const Vec3& p, const CollapseOptions& options, CheckScratch& scratch) const
{
  return this->CheckCollapseWith(vertices, count, p, options, scratch.Gathered, &scratch);
}

CollapseStatus EditableMesh::CheckCollapseWith(const Index* vertices, int count, const Vec3& p,
  const CollapseOptions& options, std::vector<Index>& scratch, CheckScratch* link) const
{
  assert(count >= 2 && count <= 3);
  for (int i = 0; i < count; ++i)
  {
    if (!this->IsVertexAlive(vertices[i]))
    {
      return CollapseStatus::DeadVertex;
    }
    if (options.LockedVertices && options.LockedVertices[vertices[i]])
    {
      return CollapseStatus::Locked;
    }
  }
  this->GatherTriangles(vertices, count, scratch);
  SurvivorNormals normals;
  normals.Wanted = options.Survivors != nullptr;
  if (options.GeometryFirst)
  {
    const CollapseStatus geometry = this->CheckGeometry(vertices, count, p, options, scratch, nullptr, normals);
    if (geometry != CollapseStatus::Ok)
    {
      return geometry;
    }
  }
  this->PrefetchGathered(scratch);
  SetScan scan;
  if (!options.AllowTopologyChange)
  {
    const CollapseStatus topology = this->CheckTopology(vertices, count, options, scratch, link, scan);
    if (topology != CollapseStatus::Ok)
    {
      return topology;
    }
  }
  if (!options.GeometryFirst)
  {
    const CollapseStatus geometry = this->CheckGeometry(vertices, count, p, options, scratch, &scan, normals);
    if (geometry != CollapseStatus::Ok)
    {
      return geometry;
    }
  }
  return this->TestSurvivors(vertices, count, p, options, scratch, normals);
}

CollapseStatus EditableMesh::CheckTopology(const Index* vertices, int count, const CollapseOptions& options,
  const std::vector<Index>& gathered, CheckScratch* scratch, SetScan& scan) const
{
  bool anyBoundary = false;
  bool onBoundary[3] = { false, false, false };
  for (int i = 0; i < count; ++i)
  {
    onBoundary[i] =
      options.BoundaryVertices ? options.BoundaryVertices[vertices[i]] != 0 : this->IsBoundaryVertex(vertices[i]);
    anyBoundary = anyBoundary || onBoundary[i];
  }
  if (!scratch && !this->VertexLinkMarks)
  {
    scratch = &this->LinkTable;
  }
  const CollapseStatus link = scratch
    ? this->CheckLink(vertices, count, anyBoundary, gathered, TableLink(*scratch, gathered.size()), scan)
    : this->CheckLink(vertices, count, anyBoundary, gathered, MarkedLink{ this->VertexLink, this->NextEpoch() }, scan);
  if (link != CollapseStatus::Ok)
  {
    return link;
  }
  if (!this->BorderVerticesFormChain(vertices, count, onBoundary))
  {
    return CollapseStatus::BoundaryChange;
  }
  return this->IsolatesVertex(vertices, count, options, gathered, scan) ? CollapseStatus::IsolatedVertex
                                                                        : CollapseStatus::Ok;
}

void EditableMesh::PrepareTrial(const Index* vertices, int count, const CollapseOptions& options, SetTrial& trial) const
{
  assert(count >= 2 && count <= 3);
  std::copy_n(vertices, count, trial.Vertices);
  trial.Count = count;
  trial.Fixed = CollapseStatus::Ok;
  trial.TopologyKnown = options.AllowTopologyChange;
  trial.FirstTested = 0;
  trial.NextGathered = 0;
  trial.Gathered.clear();
  trial.Survivors.clear();
  for (int i = 0; i < count; ++i)
  {
    if (!this->IsVertexAlive(vertices[i]))
    {
      trial.Fixed = CollapseStatus::DeadVertex;
      return;
    }
    if (options.LockedVertices && options.LockedVertices[vertices[i]])
    {
      trial.Fixed = CollapseStatus::Locked;
      return;
    }
  }
  this->GatherTriangles(vertices, count, trial.Gathered);
}

void EditableMesh::PrepareTrialAfterGeometry(
  const Index* vertices, int count, const CollapseOptions& options, std::vector<Index>& gathered, SetTrial& trial) const
{
  assert(count >= 2 && count <= 3 && !options.GeometryFirst);
  std::copy_n(vertices, count, trial.Vertices);
  trial.Count = count;
  // The check passed the dead and locked vertices and the topology before its geometry failed.
  trial.Fixed = CollapseStatus::Ok;
  trial.TopologyKnown = true;
  trial.FirstTested = 0;
  trial.NextGathered = 0;
  trial.Survivors.clear();
  trial.Gathered.swap(gathered);
  (void)options;
}

// The next surviving triangle of the gathered ones, with its old normal, length and angle (the
// same expressions as CheckGeometry's, so the same numbers); false when there is none left.
// Survivors are added as the tests reach them: a point that fails at the first triangles costs no
// more than CheckGeometry.
bool EditableMesh::AddNextSurvivor(const CollapseOptions& options, SetTrial& trial) const
{
  while (trial.NextGathered < trial.Gathered.size())
  {
    int corner = 0;
    const Index* tri = this->Triangle(trial.Gathered[trial.NextGathered++]);
    if (CountMembers(tri, trial.Vertices, trial.Count, corner) >= 2)
    {
      continue;
    }
    SetTrial::Surviving s;
    s.Corners[0] = this->Point(tri[0]);
    s.Corners[1] = this->Point(tri[1]);
    s.Corners[2] = this->Point(tri[2]);
    const Vec3* q = s.Corners;
    s.OldNormal = Cross(q[1] - q[0], q[2] - q[0]);
    s.OldLength = Norm(s.OldNormal);
    s.OldMinimumAngle = options.MinimumAngle > 0 ? MinimumAngle(q[0], q[1], q[2]) : 0.0;
    s.Triangle = trial.Gathered[trial.NextGathered - 1];
    s.Corner = corner;
    trial.Survivors.push_back(s);
    return true;
  }
  return false;
}

CollapseStatus EditableMesh::CheckTrial(const Vec3& p, const CollapseOptions& options, SetTrial& trial, CheckScratch* link) const
{
  if (trial.Fixed != CollapseStatus::Ok)
  {
    return trial.Fixed;
  }
  // CheckGeometry's tests, the triangle that failed the last point first, then the others in
  // order (each survivor once: bounded by the gathered triangles).
  const auto test = [&](size_t j) {
    SetTrial::Surviving& s = trial.Survivors[j];
    return MovedCornerStatus(s.Corners, s.Corner, p, s.OldNormal, s.OldLength, s.OldMinimumAngle, options, s.NewNormal);
  };
  // (first: none when no survivor is prepared yet)
  const size_t first = trial.FirstTested < trial.Survivors.size() ? trial.FirstTested : trial.Gathered.size();
  if (first < trial.Survivors.size())
  {
    const CollapseStatus failure = test(first);
    if (failure != CollapseStatus::Ok)
    {
      return failure;
    }
  }
  for (size_t j = 0; j < trial.Survivors.size() || this->AddNextSurvivor(options, trial); ++j)
  {
    const CollapseStatus failure = j == first ? CollapseStatus::Ok : test(j);
    if (failure != CollapseStatus::Ok)
    {
      trial.FirstTested = j;
      return failure;
    }
  }
  return this->CheckTrialTopology(options, trial, link) == CollapseStatus::Ok ? this->TestTrialSurvivors(options, trial)
                                                                                : trial.Fixed;
}

CollapseStatus EditableMesh::CheckTrialTopology(const CollapseOptions& options, SetTrial& trial, CheckScratch* link) const
{
  if (trial.Fixed == CollapseStatus::Ok && !trial.TopologyKnown)
  {
    this->PrefetchGathered(trial.Gathered);
    SetScan scan;
    trial.Fixed = this->CheckTopology(trial.Vertices, trial.Count, options, trial.Gathered, link, scan);
    trial.TopologyKnown = true;
  }
  return trial.Fixed;
}

// The caller's test (options.Survivors) of every survivor at the point CheckTrial just tested (each
// holds its new area vector from that test), in chunks.
CollapseStatus EditableMesh::TestTrialSurvivors(const CollapseOptions& options, const SetTrial& trial) const
{
  if (!options.Survivors)
  {
    return CollapseStatus::Ok;
  }
  SurvivorNormals chunk;
  for (size_t j = 0; j < trial.Survivors.size();)
  {
    chunk.Kept = 0;
    for (; j < trial.Survivors.size() && chunk.Kept < SurvivorNormals::Capacity; ++j)
    {
      chunk.Triangles[chunk.Kept] = trial.Survivors[j].Triangle;
      chunk.Normals[chunk.Kept++] = trial.Survivors[j].NewNormal;
    }
    if (!options.Survivors->Keeps(chunk.Triangles, chunk.Normals, chunk.Kept))
    {
      return CollapseStatus::Flip;
    }
  }
  return CollapseStatus::Ok;
}

void EditableMesh::Collapse(const Index* vertices, int count, Index kept, const Vec3& p, CollapseRecord* record)
{
  this->GatherTriangles(vertices, count, this->Scratch);
  this->Collapse(vertices, count, kept, p, this->Scratch, record);
}

template <typename Keep>
Index EditableMesh::MergeSet(const Index* vertices, int count, Index kept, const Vec3& p,
  const std::vector<Index>& gathered, CollapseRecord* record, Keep&& keep)
{
  if (record)
  {
    record->Clear();
    record->VertexCount = count;
    record->Kept = kept;
    record->NewPosition = p;
    for (int i = 0; i < count; ++i)
    {
      record->Vertices[i] = vertices[i];
      record->OldPositions[i] = this->Point(vertices[i]);
    }
  }
  Index removed = 0;
  for (Index t : gathered)
  {
    int corner = 0;
    const int members = CountMembers(this->Triangle(t), vertices, count, corner);
    if (members >= 2)
    {
      this->TriangleAlive[t] = 0;
      ++removed;
      if (record)
      {
        record->RemovedTriangles.push_back(t);
      }
      continue;
    }
    Index& slot = this->Triangles[3 * size_t(t) + corner];
    if (slot != kept)
    {
      if (record)
      {
        record->ChangedTriangles.push_back(t);
        record->ChangedCorner.push_back(static_cast<unsigned char>(corner));
        record->ChangedFrom.push_back(slot);
      }
      slot = kept;
    }
    keep(t);
  }
  for (int i = 0; i < count; ++i)
  {
    if (vertices[i] != kept)
    {
      this->VertexAlive[vertices[i]] = 0;
      this->RefCount[vertices[i]] = 0;
    }
  }
  this->SetPoint(kept, p);
  return removed;
}

void EditableMesh::Collapse(const Index* vertices, int count, Index kept, const Vec3& p,
  const std::vector<Index>& gathered, CollapseRecord* record)
{
  this->ScratchBlock.clear();
  this->LiveTriangles -=
    this->MergeSet(vertices, count, kept, p, gathered, record, [&](Index t) { this->ScratchBlock.push_back(t); });
  for (int i = 0; i < count; ++i)
  {
    this->LiveVertices -= vertices[i] != kept ? 1 : 0;
  }
  this->AppendBlock(kept, this->ScratchBlock);
  this->CompactIfNeeded();
}

Index EditableMesh::ReserveRefs(Index count)
{
  const Index start = static_cast<Index>(this->Refs.size());
  this->Refs.resize(this->Refs.size() + size_t(count));
  return start;
}

Index EditableMesh::CollapseIntoBlock(const Index* vertices, int count, Index kept, const Vec3& p,
  const std::vector<Index>& gathered, Index blockStart, CollapseRecord& record)
{
  Index* block = this->Refs.data() + blockStart;
  Index n = 0;
  const Index removed = this->MergeSet(vertices, count, kept, p, gathered, &record, [&](Index t) { block[n++] = t; });
  this->RefStart[kept] = blockStart;
  this->RefCount[kept] = n;
  return removed;
}

Index EditableMesh::CollapseAppending(const Index* vertices, int count, Index kept, const Vec3& p,
  const std::vector<Index>& gathered, CollapseRecord& record)
{
  // Room for every gathered triangle, trimmed to the survivors written.
  const Index start = static_cast<Index>(this->Refs.size());
  this->Refs.resize(this->Refs.size() + gathered.size());
  const Index removed = this->CollapseIntoBlock(vertices, count, kept, p, gathered, start, record);
  this->Refs.resize(size_t(start) + size_t(this->RefCount[kept]));
  return removed;
}

Index EditableMesh::RemovedBy(const Index* vertices, int count, const std::vector<Index>& gathered) const
{
  Index removed = 0;
  for (Index t : gathered)
  {
    int corner = 0;
    removed += CountMembers(this->Triangle(t), vertices, count, corner) >= 2 ? 1 : 0;
  }
  return removed;
}

void EditableMesh::FinishCollapses(Index removedTriangles, Index removedVertices)
{
  this->LiveTriangles -= removedTriangles;
  this->LiveVertices -= removedVertices;
  this->CompactIfNeeded();
}

void EditableMesh::Undo(const CollapseRecord& record)
{
  const Index kept = record.Kept;
  for (int i = 0; i < record.VertexCount; ++i)
  {
    const Index v = record.Vertices[i];
    if (v != kept)
    {
      this->VertexAlive[v] = 1;
      ++this->LiveVertices;
    }
    this->SetPoint(v, record.OldPositions[i]);
  }
  for (size_t i = 0; i < record.ChangedTriangles.size(); ++i)
  {
    this->Triangles[3 * size_t(record.ChangedTriangles[i]) + record.ChangedCorner[i]] = record.ChangedFrom[i];
  }
  for (Index t : record.RemovedTriangles)
  {
    this->TriangleAlive[t] = 1;
    ++this->LiveTriangles;
  }
  // Candidates for the blocks of the set: kept's current triangles plus the revived ones.
  // Member scratch vectors: vertex splits run in long sequences (progressive meshes), so no
  // allocation per split.
  std::vector<Index>& candidates = this->Scratch;
  std::vector<Index>& block = this->ScratchBlock;
  candidates.clear();
  this->ForEachTriangle(kept, [&](Index t) { candidates.push_back(t); });
  candidates.insert(candidates.end(), record.RemovedTriangles.begin(), record.RemovedTriangles.end());
  for (int i = 0; i < record.VertexCount; ++i)
  {
    const Index v = record.Vertices[i];
    block.clear();
    for (Index t : candidates)
    {
      const Index* tri = this->Triangle(t);
      if (tri[0] == v || tri[1] == v || tri[2] == v)
      {
        block.push_back(t);
      }
    }
    this->AppendBlock(v, block);
  }
  // Other vertices of revived triangles may have lost them from their blocks in a compaction.
  for (Index t : record.RemovedTriangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index x = this->Triangle(t)[k];
      if (std::find(record.Vertices.begin(), record.Vertices.begin() + record.VertexCount, x) !=
        record.Vertices.begin() + record.VertexCount)
      {
        continue;
      }
      const Index* refs = this->Refs.data() + this->RefStart[x];
      if (std::find(refs, refs + this->RefCount[x], t) == refs + this->RefCount[x])
      {
        block.assign(refs, refs + this->RefCount[x]);
        block.push_back(t);
        this->AppendBlock(x, block);
      }
    }
  }
  this->CompactIfNeeded();
}

bool EditableMesh::FlipEdge(Index x, Index y, FlipRecord* record)
{
  if (x == y || !this->VertexAlive[x] || !this->VertexAlive[y])
  {
    return false;
  }
  Index t0 = InvalidIndex, t1 = InvalidIndex, q = InvalidIndex, z = InvalidIndex;
  int count = 0;
  this->ForEachTriangle(x, [&](Index t) {
    const Index* tri = this->Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] == x && tri[(k + 1) % 3] == y)
      {
        t0 = t;
        q = tri[(k + 2) % 3];
        ++count;
      }
      else if (tri[k] == y && tri[(k + 1) % 3] == x)
      {
        t1 = t;
        z = tri[(k + 2) % 3];
        ++count;
      }
    }
  });
  if (count != 2 || t0 == InvalidIndex || t1 == InvalidIndex || q == z)
  {
    return false;
  }
  bool joined = false;
  this->ForEachTriangle(q, [&](Index t) {
    const Index* tri = this->Triangle(t);
    joined = joined || tri[0] == z || tri[1] == z || tri[2] == z;
  });
  if (joined)
  {
    return false;
  }
  Index* a = &this->Triangles[3 * size_t(t0)];
  Index* b = &this->Triangles[3 * size_t(t1)];
  for (int k = 0; k < 3; ++k)
  {
    a[k] = a[k] == y ? z : a[k]; // (X, Y, Q) -> (X, Z, Q)
    b[k] = b[k] == x ? q : b[k]; // (Y, X, Z) -> (Y, Q, Z) = (Z, Y, Q)
  }
  this->ReplaceInBlock(y, t0, InvalidIndex);
  this->ReplaceInBlock(z, InvalidIndex, t0);
  this->ReplaceInBlock(x, t1, InvalidIndex);
  this->ReplaceInBlock(q, InvalidIndex, t1);
  this->CompactIfNeeded();
  if (record)
  {
    record->Triangles[0] = t0;
    record->Triangles[1] = t1;
    record->X = x;
    record->Y = y;
    record->Q = q;
    record->Z = z;
  }
  return true;
}

void EditableMesh::Undo(const FlipRecord& record)
{
  const Index t0 = record.Triangles[0], t1 = record.Triangles[1];
  Index* a = &this->Triangles[3 * size_t(t0)];
  Index* b = &this->Triangles[3 * size_t(t1)];
  for (int k = 0; k < 3; ++k)
  {
    a[k] = a[k] == record.Z ? record.Y : a[k];
    b[k] = b[k] == record.Q ? record.X : b[k];
  }
  this->ReplaceInBlock(record.Z, t0, InvalidIndex);
  this->ReplaceInBlock(record.Y, InvalidIndex, t0);
  this->ReplaceInBlock(record.Q, t1, InvalidIndex);
  this->ReplaceInBlock(record.X, InvalidIndex, t1);
  this->CompactIfNeeded();
}

void EditableMesh::ReplaceInBlock(Index v, Index removed, Index added)
{
  const Index* refs = this->Refs.data() + this->RefStart[v];
  this->ScratchBlock.clear();
  for (Index i = 0, n = this->RefCount[v]; i < n; ++i)
  {
    if (refs[i] != removed)
    {
      this->ScratchBlock.push_back(refs[i]);
    }
  }
  if (added != InvalidIndex)
  {
    this->ScratchBlock.push_back(added);
  }
  this->AppendBlock(v, this->ScratchBlock);
}

Index EditableMesh::AddTriangle(Index a, Index b, Index c)
{
  const Index t = this->NumberOfTriangles();
  this->Triangles.insert(this->Triangles.end(), { a, b, c });
  this->TriangleAlive.push_back(1);
  ++this->LiveTriangles;
  std::vector<Index>& block = this->ScratchBlock;
  for (Index v : { a, b, c })
  {
    const Index* refs = this->Refs.data() + this->RefStart[v];
    block.assign(refs, refs + this->RefCount[v]);
    block.push_back(t);
    this->AppendBlock(v, block);
  }
  this->CompactIfNeeded();
  return t;
}

void EditableMesh::RemoveTriangle(Index t)
{
  if (this->TriangleAlive[t])
  {
    this->TriangleAlive[t] = 0;
    --this->LiveTriangles;
  }
}

void EditableMesh::AppendBlock(Index v, const std::vector<Index>& triangles)
{
  this->RefStart[v] = static_cast<Index>(this->Refs.size());
  this->RefCount[v] = static_cast<Index>(triangles.size());
  this->Refs.insert(this->Refs.end(), triangles.begin(), triangles.end());
}

void EditableMesh::CompactIfNeeded()
{
  if (this->Refs.size() <= this->CompactThreshold)
  {
    return;
  }
  // Rebuild when the garbage reaches the live size (counting what the compactions in place took
  // out since the last rebuild): with or without a room limit the rebuilds come at the same
  // collapses, so a limited mesh's fans are in the same order as an unlimited one's.
  if (this->Refs.size() + this->CompactedAway > this->RebuildThreshold)
  {
    this->RebuildBlocks();
    this->CompactedAway = 0;
    this->RebuildThreshold = std::max<size_t>(2 * this->Refs.size(), 1024);
  }
  else
  {
    const size_t before = this->Refs.size();
    this->CompactInOrder();
    this->CompactedAway += before - this->Refs.size();
  }
  if (this->RoomLimit == 0 && this->RoomFactor > 0)
  {
    this->RoomLimit = static_cast<size_t>(this->RoomFactor * double(this->Refs.size()));
  }
  // Reserving up to the next compaction (plus room for the blocks appended before the next check)
  // keeps the vector from doubling past it (peak memory). With a room limit, in place before the
  // array passes it, but never with less than an eighth of the live size as room (so that
  // compactions stay a share of the appends), and never after the next rebuild.
  const size_t rebuildAt = this->RebuildThreshold - this->CompactedAway;
  this->CompactThreshold = rebuildAt;
  if (this->RoomLimit > 0)
  {
    this->CompactThreshold =
      std::min(rebuildAt, std::max(this->RoomLimit, this->Refs.size() + this->Refs.size() / 8 + 1024));
  }
  if (this->Refs.capacity() > 2 * (this->CompactThreshold + 4096))
  {
    // The mesh shrank to under a quarter of the room held: give the rest back (same contents).
    std::vector<Index>(this->Refs).swap(this->Refs);
  }
  ReserveOnHugePages(this->Refs, this->CompactThreshold + 4096);
}

void EditableMesh::CompactInOrder()
{
  // Each live vertex's block start is marked in the array (-1 - v, triangle ids are never
  // negative; the reference it covers waits in RefStart[v]), then one walk in array order moves
  // every marked block's live references down, in their order, over the garbage before it.
  const Index np = this->NumberOfPoints();
  for (Index v = 0; v < np; ++v)
  {
    if (!this->VertexAlive[v] || this->RefCount[v] == 0)
    {
      this->RefStart[v] = 0; // an empty block, inside the array
      this->RefCount[v] = 0;
      continue;
    }
    const Index start = this->RefStart[v];
    this->RefStart[v] = this->Refs[size_t(start)];
    this->Refs[size_t(start)] = -1 - v;
  }
  size_t write = 0;
  for (size_t read = 0; read < this->Refs.size();)
  {
    if (this->Refs[read] >= 0)
    {
      ++read; // garbage
      continue;
    }
    const Index v = -1 - this->Refs[read];
    const Index first = this->RefStart[v], count = this->RefCount[v];
    const size_t begin = write;
    if (this->TriangleAlive[first])
    {
      this->Refs[write++] = first;
    }
    for (Index i = 1; i < count; ++i)
    {
      const Index t = this->Refs[read + size_t(i)];
      if (this->TriangleAlive[t])
      {
        this->Refs[write++] = t;
      }
    }
    this->RefStart[v] = static_cast<Index>(begin);
    this->RefCount[v] = static_cast<Index>(write - begin);
    read += size_t(count);
  }
  this->Refs.resize(write);
}

void EditableMesh::RebuildBlocks()
{
  // Rebuild every block from the live triangles (drops garbage and dead references): each
  // vertex's triangles in id order, in parallel with SetParallelRebuild(true).
  std::fill(this->RefCount.begin(), this->RefCount.end(), 0);
  GroupByKey(
    3 * this->NumberOfTriangles(), this->NumberOfPoints(),
    [this](Index i) { return this->TriangleAlive[size_t(i / 3)] ? this->Triangles[size_t(i)] : Index(-1); },
    [](Index i) { return i / 3; }, this->RefStart.data(), this->RefCount.data(), this->Refs, this->ParallelRebuild);
}

void EditableMesh::Extract(TriangleMesh& out, std::vector<Index>* newToOld) const
{
  out.Points.clear();
  out.Triangles.clear();
  std::vector<Index> oldToNew(this->NumberOfPoints(), InvalidIndex);
  if (newToOld)
  {
    newToOld->clear();
  }
  for (Index t = 0; t < this->NumberOfTriangles(); ++t)
  {
    if (!this->TriangleAlive[t])
    {
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      const Index v = this->Triangles[3 * size_t(t) + k];
      if (oldToNew[v] == InvalidIndex)
      {
        oldToNew[v] = out.AddPoint(this->Point(v));
        if (newToOld)
        {
          newToOld->push_back(v);
        }
      }
      out.Triangles.push_back(oldToNew[v]);
    }
  }
}

bool EditableMesh::CheckInvariants() const
{
  // Every live triangle is in the block of each of its vertices, all of which are alive.
  for (Index t = 0; t < this->NumberOfTriangles(); ++t)
  {
    if (!this->TriangleAlive[t])
    {
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      const Index v = this->Triangles[3 * size_t(t) + k];
      if (!this->VertexAlive[v])
      {
        return false;
      }
      const Index* refs = this->Refs.data() + this->RefStart[v];
      if (std::find(refs, refs + this->RefCount[v], t) == refs + this->RefCount[v])
      {
        return false;
      }
    }
  }
  // Every live reference points at a triangle that contains the vertex.
  for (Index v = 0; v < this->NumberOfPoints(); ++v)
  {
    bool ok = true;
    this->ForEachTriangle(v, [&](Index t) {
      const Index* tri = this->Triangle(t);
      ok = ok && (tri[0] == v || tri[1] == v || tri[2] == v);
    });
    if (!ok)
    {
      return false;
    }
  }
  return true;
}

size_t EditableMesh::MemoryBytes() const
{
  return this->Points.capacity() * sizeof(double) +
    (this->Triangles.capacity() + this->RefStart.capacity() + this->RefCount.capacity() + this->Refs.capacity() +
      this->Scratch.capacity() + this->ScratchBlock.capacity()) *
    sizeof(Index) +
    this->TriangleAlive.capacity() + this->VertexAlive.capacity() + this->VertexLink.capacity() * sizeof(LinkEntry) +
    (this->LinkTable.Gathered.capacity() + this->LinkTable.Keys.capacity()) * sizeof(Index) +
    this->LinkTable.Links.capacity() * sizeof(this->LinkTable.Links[0]);
}
} // namespace slod
