// SPDX-License-Identifier: BSD-3-Clause
// The one collapse-record model (slodCollapseRecords.h): appending the collapses and flips made
// on a real mesh, undoing every record gives the input back bit for bit, redoing them gives the
// simplified mesh back, the table form reads back the same records, and the memory figure covers
// what is stored.
#include "TestSupport.h"

#include "slodCollapseRecordTable.h"
#include "slodCollapseRecords.h"
#include "slodEditableMesh.h"
#include "slodMeshTopology.h"

#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkTable.h"

#include <gtest/gtest.h>

using namespace slod;
using namespace slodtest;

namespace
{
// Everything of an EditableMesh a replay must restore: per slot the alive flag and the corners,
// per vertex the alive flag and the exact position.
struct Snapshot
{
  std::vector<Index> Triangles;
  std::vector<unsigned char> TriangleAlive, VertexAlive;
  std::vector<double> Points;

  explicit Snapshot(const EditableMesh& mesh)
  {
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      this->Triangles.insert(this->Triangles.end(), mesh.Triangle(t), mesh.Triangle(t) + 3);
      this->TriangleAlive.push_back(mesh.IsTriangleAlive(t) ? 1 : 0);
    }
    for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
    {
      this->VertexAlive.push_back(mesh.IsVertexAlive(v) ? 1 : 0);
      const Vec3 p = mesh.Point(v);
      this->Points.insert(this->Points.end(), p.begin(), p.end());
    }
  }
  bool operator==(const Snapshot& o) const
  {
    return this->Triangles == o.Triangles && this->TriangleAlive == o.TriangleAlive &&
      this->VertexAlive == o.VertexAlive && this->Points == o.Points;
  }
};

// Simplifies `mesh` by alternating triangle collapses (to the centroid) and edge collapses (to the
// midpoint), with an edge flip after every seventh collapse, appending each edit to `records`.
// At most `steps` collapses; returns the number made.
Index CollapseAndRecord(EditableMesh& mesh, Index steps, CollapseRecords& records)
{
  CollapseRecord record;
  Index done = 0;
  for (Index t = 0; t < mesh.NumberOfTriangles() && done < steps; ++t)
  {
    if (!mesh.IsTriangleAlive(t))
    {
      continue;
    }
    const Index* tri = mesh.Triangle(t);
    const Index set[3] = { tri[1], tri[2], tri[0] }; // the kept vertex is not the first listed
    const int count = done % 2 == 0 ? 3 : 2;
    Vec3 p = mesh.Point(set[0]) + mesh.Point(set[1]);
    p = count == 3 ? (1.0 / 3) * (p + mesh.Point(set[2])) : 0.5 * p;
    if (mesh.CheckCollapse(set, count, p) != CollapseStatus::Ok)
    {
      continue;
    }
    mesh.Collapse(set, count, set[count - 1], p, &record);
    records.Append(record, mesh);
    ++done;
    FlipRecord flip;
    if (done % 7 == 0 && mesh.IsTriangleAlive(t + 1 < mesh.NumberOfTriangles() ? t + 1 : t))
    {
      const Index* next = mesh.Triangle(t + 1 < mesh.NumberOfTriangles() ? t + 1 : t);
      if (mesh.FlipEdge(next[0], next[1], &flip))
      {
        records.AppendFlip(flip);
      }
    }
  }
  return done;
}

TriangleMesh RealMesh()
{
  return ToTriangleMesh(LoadTestMesh("fandisk"));
}
} // namespace

TEST(CollapseRecords, UndoEveryRecordGivesTheInputBitForBitAndRedoTheSimplifiedMesh)
{
  const TriangleMesh input = RealMesh();
  EditableMesh mesh(input);
  const Snapshot original(mesh);
  CollapseRecords records;
  const Index made = CollapseAndRecord(mesh, input.NumberOfTriangles() / 4, records);
  ASSERT_GT(made, input.NumberOfTriangles() / 8);
  ASSERT_EQ(records.NumberOfCollapses(), made);
  ASSERT_GT(records.NumberOfFlips(), 0);
  ASSERT_TRUE(mesh.CheckInvariants());
  const Snapshot simplified(mesh);
  const MeshStatistics before = ComputeMeshStatistics(input);

  CollapseRecord scratch;
  for (Index k = made - 1; k >= 0; --k)
  {
    records.Undo(k, mesh, scratch);
  }
  ASSERT_TRUE(mesh.CheckInvariants());
  EXPECT_TRUE(Snapshot(mesh) == original);
  EXPECT_EQ(mesh.NumberOfLiveTriangles(), input.NumberOfTriangles());
  EXPECT_EQ(mesh.NumberOfLiveVertices(), input.NumberOfPoints());

  for (Index k = 0; k < made; ++k)
  {
    records.Redo(k, mesh, scratch);
  }
  ASSERT_TRUE(mesh.CheckInvariants());
  EXPECT_TRUE(Snapshot(mesh) == simplified);
  TriangleMesh out;
  mesh.Extract(out);
  const MeshStatistics after = ComputeMeshStatistics(out);
  EXPECT_EQ(after.EulerCharacteristic, before.EulerCharacteristic);
  EXPECT_EQ(after.BoundaryLoops, before.BoundaryLoops);
  EXPECT_EQ(after.NonManifoldEdges, 0);
}

// Records stored in the mesh's own ids (kept vertex first, whatever order the set had).
TEST(CollapseRecords, GetReturnsTheRecordOfTheCollapseKeptFirst)
{
  EditableMesh mesh(RealMesh());
  CollapseRecords records;
  CollapseAndRecord(mesh, 50, records);
  CollapseRecord record;
  for (Index k = 0; k < records.NumberOfCollapses(); ++k)
  {
    records.Get(k, record);
    ASSERT_EQ(record.Kept, record.Vertices[0]);
    ASSERT_EQ(record.VertexCount, k % 2 == 0 ? 3 : 2);
    ASSERT_FALSE(mesh.IsVertexAlive(record.Vertices[1]));
    // A triangle collapse removes the triangle and up to its three edge neighbours, an edge collapse up to two.
    ASSERT_GE(records.RemovedCount(k), 1);
    ASSERT_LE(records.RemovedCount(k), 4);
  }
}

// A redirected corner is stored as its triangle and one byte (the corner and the position of the
// vertex it had among the collapse's merged vertices, never the kept one): 5 bytes instead of 9.
// What Get hands back is what the mesh's own record said (checked against records kept whole).
TEST(CollapseRecords, RedirectedCornersTakeATriangleAndOneByte)
{
  const TriangleMesh input = RealMesh();
  EditableMesh mesh(input);
  CollapseRecords records;
  records.StorePositions = records.StoreRemovedTriangleVertices = false;
  std::vector<CollapseRecord> whole;
  CollapseRecord record;
  for (Index t = 0; t < input.NumberOfTriangles() && Index(whole.size()) < 300; t += 7)
  {
    if (!mesh.IsTriangleAlive(t))
    {
      continue;
    }
    const Index* tri = mesh.Triangle(t);
    const Index set[2] = { tri[0], tri[1] };
    const Vec3 p = 0.5 * (mesh.Point(set[0]) + mesh.Point(set[1]));
    if (mesh.CheckCollapse(set, 2, p) != CollapseStatus::Ok)
    {
      continue;
    }
    record.Clear();
    mesh.Collapse(set, 2, set[whole.size() % 2], p, &record);
    records.Append(record, mesh);
    whole.push_back(record);
  }
  ASSERT_GT(whole.size(), 100u);
  size_t changed = 0;
  for (Index k = 0; k < records.NumberOfCollapses(); ++k)
  {
    const CollapseRecord& made = whole[size_t(k)];
    records.Get(k, record);
    ASSERT_EQ(record.ChangedTriangles, made.ChangedTriangles);
    ASSERT_EQ(record.ChangedCorner, made.ChangedCorner);
    ASSERT_EQ(record.ChangedFrom, made.ChangedFrom);
    for (size_t c = size_t(records.ChangedOffsets[k]); c < size_t(records.ChangedOffsets[k + 1]); ++c)
    {
      EXPECT_NE(records.ChangedFrom(k, c), records.Kept(k));
    }
    changed += made.ChangedTriangles.size();
  }
  ASSERT_GT(changed, whole.size());
  const size_t n = whole.size(), removed = records.RemovedTriangles.size();
  for (auto* v : { &records.Vertices, &records.RemovedOffsets, &records.RemovedTriangles, &records.ChangedOffsets,
         &records.ChangedTriangles })
  {
    v->shrink_to_fit();
  }
  records.ChangedCodes.shrink_to_fit();
  // (+1: the surrounding vertices' first offset, not stored here)
  EXPECT_LE(records.MemoryBytes(), (3 * n + 2 * (n + 1) + 1 + removed) * sizeof(Index) + 5 * changed);
}

TEST(CollapseRecords, TableReadsBackTheSameRecords)
{
  const TriangleMesh input = RealMesh();
  EditableMesh mesh(input);
  CollapseRecords records;
  CollapseAndRecord(mesh, 400, records);
  records.Flips.clear(); // the table holds collapses only (the triangle collapse makes no flips)
  records.FlipStamps.clear();
  vtkNew<vtkTable> table;
  CollapseRecordsToTable(records, input.NumberOfPoints(), input.NumberOfTriangles(), table);
  EXPECT_EQ(table->GetNumberOfRows(), records.NumberOfCollapses());
  CollapseRecords back;
  Index points = 0, triangles = 0;
  ASSERT_TRUE(TableToCollapseRecords(table, back, points, triangles));
  EXPECT_EQ(points, input.NumberOfPoints());
  EXPECT_EQ(triangles, input.NumberOfTriangles());
  EXPECT_EQ(back.Vertices, records.Vertices);
  EXPECT_EQ(back.OldPositions, records.OldPositions);
  EXPECT_EQ(back.NewPositions, records.NewPositions);
  EXPECT_EQ(back.RemovedOffsets, records.RemovedOffsets);
  EXPECT_EQ(back.RemovedTriangles, records.RemovedTriangles);
  EXPECT_EQ(back.RemovedTriangleVertices, records.RemovedTriangleVertices);
  EXPECT_EQ(back.ChangedOffsets, records.ChangedOffsets);
  EXPECT_EQ(back.ChangedTriangles, records.ChangedTriangles);
  EXPECT_EQ(back.ChangedCodes, records.ChangedCodes);

  // A vertex id beyond the input is a malformed table, not a crash later.
  vtkDataArray::SafeDownCast(table->GetColumnByName("Vertices"))->SetComponent(0, 1, input.NumberOfPoints());
  EXPECT_FALSE(TableToCollapseRecords(table, back, points, triangles));
}

// The memory figure covers every stored element, and topology-only records (an owner that keeps
// the positions, as the hierarchy) save the 12 doubles of positions per collapse and 3 ids per
// removed triangle.
TEST(CollapseRecords, MemoryBytesCoverWhatIsStored)
{
  const TriangleMesh input = RealMesh();
  CollapseRecords full, topology;
  topology.StorePositions = topology.StoreRemovedTriangleVertices = false;
  for (CollapseRecords* records : { &full, &topology })
  {
    EditableMesh mesh(input);
    CollapseAndRecord(mesh, 300, *records);
  }
  ASSERT_EQ(full.NumberOfCollapses(), topology.NumberOfCollapses());
  const size_t n = size_t(full.NumberOfCollapses());
  const size_t removed = full.RemovedTriangles.size(), changed = full.ChangedTriangles.size();
  const size_t stored = (3 * n + 2 * (n + 1) + 4 * removed + changed + full.FlipStamps.size()) * sizeof(Index) +
    changed + 12 * n * sizeof(double) + full.Flips.size() * sizeof(FlipRecord);
  EXPECT_GE(full.MemoryBytes(), stored);
  EXPECT_TRUE(topology.OldPositions.empty() && topology.NewPositions.empty());
  EXPECT_TRUE(topology.RemovedTriangleVertices.empty());
  EXPECT_EQ(topology.Vertices, full.Vertices);
  EXPECT_EQ(topology.ChangedCodes, full.ChangedCodes);
  topology.Clear();
  EXPECT_EQ(topology.NumberOfCollapses(), 0);
  EXPECT_FALSE(topology.StorePositions); // Clear keeps what is stored
}
