// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm GreedyCuts: a final pass of half-edge collapses whose error bound is proved.
//
// The greedy cuts' output is epsilon-close to the input both ways, but each patch was cut alone,
// inside its simplified boundary chains: many of its vertices (chain vertices above all) are not
// needed for the bound. This pass removes output vertices by half-edge collapses u -> v (v an
// output vertex, so the output keeps original vertices only), each accepted only when the bound is
// proved again for what it changes:
//  - output -> input: every new triangle within epsilon of the input (TriangleWithinDistance,
//    rigorous adaptive subdivision against the input's BVH), and facing the input at its centroid;
//  - input -> output: every input triangle that could have had its nearest output point in u's old
//    star (it comes within epsilon of one of the star's triangles, by a conservative sphere test)
//    is proved within epsilon of the new star and the triangles around it (a subset of the new
//    output, so the proof holds for the whole output); the other input points keep their nearest
//    output triangle, which the collapse does not touch;
//  - topology: EditableMesh::CheckCollapse (link condition, no flip); a border vertex only along
//    its border loop (BorderCollapses), and no loop closes; a border collapse leaves no border
//    vertex with more than 12 triangles and no new triangle under 5 degrees (unless its star had
//    one as thin).
// Between two collapse passes, interior edges are flipped where that makes the thinner of their two
// triangles fatter (fewer slivers), each flip proved the same way. Last, each triangle under 5
// degrees has its edges flipped or loses a vertex by a collapse that raises the smallest angle
// around, proved the same way (at a count target only the flips).
// Hence the two-sided Hausdorff bound of the greedy cuts survives every accepted collapse.
#ifndef slodProvedCollapses_h
#define slodProvedCollapses_h

#include "slodFilterContract.h"
#include "slodTriangleBVH.h"
#include "slodTriangleMesh.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace slod
{
// Values keyed by a triangle's three corners in order (the same triangle tried again is the same
// key): a flat table, open addressing with linear probing, at most half full, so a look-up reads a
// slot or two and an insertion allocates nothing but the table's own growth (a node map allocated
// one node per triangle ever proved: 4.8 million at 1M input triangles, read at random). Both the
// answers of one run's new triangles and those carried between runs are held this way.
template <typename Value>
class TriangleKeyTable
{
public:
  const Value* Find(const Index* key) const
  {
    if (this->Slots.empty())
    {
      return nullptr;
    }
    for (size_t i = this->Home(key);; i = (i + 1) & this->Mask) // ends: at least half the slots are free
    {
      const Slot& slot = this->Slots[i];
      if (slot.Key[0] == InvalidIndex)
      {
        return nullptr;
      }
      if (slot.Key[0] == key[0] && slot.Key[1] == key[1] && slot.Key[2] == key[2])
      {
        return &slot.Stored;
      }
    }
  }
  Value* Find(const Index* key) { return const_cast<Value*>(static_cast<const TriangleKeyTable&>(*this).Find(key)); }

  // Adds a key not present. When the table would pass half full, the entries `keep` refuses are
  // dropped first (e.g. triangles with a removed corner, never asked again), and the slots double
  // only while the kept entries still fill a quarter of them: the size follows the kept entries.
  template <typename Keep>
  void Insert(const Index* key, const Value& value, const Keep& keep)
  {
    if (2 * (this->Count + 1) > this->Slots.size())
    {
      this->Grow(keep);
    }
    this->Place(Slot{ { key[0], key[1], key[2] }, value });
  }
  void Insert(const Index* key, const Value& value)
  {
    this->Insert(key, value, [](const Index*) { return true; });
  }

  void Clear()
  {
    std::vector<Slot>().swap(this->Slots); // the memory too: Clear is the bound on it
    this->Mask = this->Count = 0;
  }
  size_t Size() const { return this->Count; }
  long long Dropped = 0; // entries `keep` refused when the table grew

private:
  struct Slot
  {
    Index Key[3] = { InvalidIndex, InvalidIndex, InvalidIndex };
    Value Stored{};
  };

  size_t Home(const Index* key) const
  {
    std::uint64_t h = std::uint32_t(key[0]);
    h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(key[1]);
    h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(key[2]);
    return size_t(h ^ (h >> 29)) & this->Mask;
  }

  void Place(const Slot& entry)
  {
    size_t i = this->Home(entry.Key);
    while (this->Slots[i].Key[0] != InvalidIndex)
    {
      i = (i + 1) & this->Mask;
    }
    this->Slots[i] = entry;
    ++this->Count;
  }

  // The kept entries are counted first and then placed straight from the old slots (no copy of
  // them in between: the growth's peak is the old and the new slots).
  template <typename Keep>
  void Grow(const Keep& keep)
  {
    size_t kept = 0;
    for (const Slot& slot : this->Slots)
    {
      kept += slot.Key[0] != InvalidIndex && keep(slot.Key);
    }
    size_t capacity = std::max<size_t>(this->Slots.size(), 1024);
    while (4 * (kept + 1) > capacity)
    {
      capacity *= 2;
    }
    std::vector<Slot> old(capacity, Slot());
    old.swap(this->Slots);
    this->Mask = capacity - 1;
    this->Count = 0;
    for (const Slot& slot : old)
    {
      if (slot.Key[0] == InvalidIndex)
      {
        continue;
      }
      if (keep(slot.Key))
      {
        this->Place(slot);
      }
      else
      {
        ++this->Dropped;
      }
    }
  }

  std::vector<Slot> Slots;
  size_t Mask = 0, Count = 0;
};

// New triangles' answers that outlive one call (session 35). A triangle of input vertices proved
// within a tolerance of the input is within every larger one, and one that does not face the input
// at its centroid never will (neither depends on the output around it), so calls at rising
// tolerances over the same input (a chain of ladder levels, RunLevels) recall them instead of
// proving them again; a refusal by the proof is not carried (a larger tolerance may prove it).
class SURFACELODFILTERS_EXPORT CarriedTriangleProofs
{
public:
  // 1: proved within `tolerance` (or facing and proved within a smaller one), -1: does not face
  // the input, 0: unknown.
  int Recall(const Index* corners, double tolerance) const;
  void Proved(const Index* corners, double tolerance);
  void DoesNotFace(const Index* corners);
  void Clear() { this->Verdicts.Clear(); }
  size_t Size() const { return this->Verdicts.Size(); }

private:
  // Per triangle (its corners in order): the smallest tolerance it was proved within, rounded up
  // to a float (a recall may then prove again what it could have recalled, never the reverse: the
  // same decisions in a 16-byte slot); a negative value when it does not face the input.
  TriangleKeyTable<float> Verdicts;
};

struct SURFACELODFILTERS_EXPORT ProvedCollapseParameters
{
  double Epsilon = 0.0;        // absolute bound (> 0)
  int SubdivisionDepth = 10;   // depth of the adaptive distance proofs
  double MinimumAngle = 0.0;   // degrees: a collapse may not make a triangle thinner than this (unless it was)
  int MaximumRounds = 8;       // passes over the output vertices (stops earlier when one removes none)
  int MaximumNeighbours = 16;  // targets tried per vertex and pass (nearest first)
  // Border vertices are collapsed too, onto a neighbour along their border loop (a loop keeps at
  // least four vertices; the loops and their number stay), guarded (no border fan over 12
  // triangles, no new sliver unless the star had one, none next to a fan over 128). Off: border
  // vertices stay.
  bool BorderCollapses = true;
  // Stop as soon as the output has at most this many triangles (0: no count target). A collapse
  // removes one or two triangles, so a reachable target is met exactly or one below.
  Index TargetTriangles = 0;
  // Work bound: no further collapse or flip is tried once the caller's piece counter (the
  // `proofPieces` argument) exceeds this value (0: only the bounds above). The output is valid
  // whenever the passes stop: every change already made was proved.
  long long MaximumProofPieces = 0;
  // Per input vertex, 1 = locked (nullptr: none): no collapse removes it or moves onto it
  // (CollapseOptions::LockedVertices). GreedyCuts locks the non-manifold vertices: the link condition
  // assumes one fan per vertex. Flips need no lock: a non-manifold edge is never flipped (it has
  // more than two triangles), and a flip's new edge must be no edge yet.
  const unsigned char* LockedVertices = nullptr;
  // A staged run's lower stage (GreedyCutsParameters::CollapseStages): the new triangles must lie
  // within this distance (<= Epsilon) of the input; the input's proofs stay at Epsilon, the bound
  // that holds on entry. 0: Epsilon.
  double NewTriangleTolerance = 0.0;
  // Only the collapse passes (no flips, no sliver step): a staged run's lower stages, and every
  // level of a chain in collapse-only steps (GreedyCutsParameters::LadderCollapsesOnly).
  bool CollapsesOnly = false;
  // Only the flips (the flip passes, then the sliver step's flips, no collapse): the count stays.
  // The finish of a chain whose levels ran in collapse-only steps.
  bool FlipsOnly = false;
  // The tries of one vertex (up to MaximumNeighbours targets) replace the same star: its sphere,
  // the unchanged output around it and the input triangles that may rely on it are gathered once
  // for all of them. Off: gathered for each target (the reference path: the same outputs, proofs
  // and pieces, more gatherings).
  bool ReuseStarGathering = true;
  // A sliver step (as the last one) also runs first, on the entry triangles: the cuts' slivers
  // (caps of ears, needles) are flipped or collapsed away while the bound is not yet used up
  // around them by the collapses (session 31). Not in CollapsesOnly stages.
  bool EarlySliverStep = false;
  // Each input triangle remembers one output triangle it lies within epsilon of on its own (its
  // three corners are: the distance to one triangle is convex), its witness. A change then re-proves
  // only the input triangles near it whose witness it replaces (or that have none), and accepts
  // without the local output when each of those finds a new witness among the new triangles and
  // the unchanged ones around them. Off: every input triangle near the change is proved against the
  // local output (the reference path; same bound, more work at large tolerances).
  bool Witnesses = true;
  // Answers carried from earlier calls over the same input and into later ones (nullptr: this
  // call's own only). The decisions are those of proving again (the proofs are monotone in the
  // tolerance); only the work differs.
  CarriedTriangleProofs* CarriedProofs = nullptr;
  // The collapse passes' order: vertices by their shortest incident edge, grouped in bands of
  // this many per doubling of its length over epsilon, and within a band in the Morton order of their
  // positions, so consecutive tries read neighbouring parts of the mesh, the input's BVH, the
  // witnesses and the index (the exact shortest-first order walks them at random: the cost per
  // try grew with the input's size). 0: the exact order (shortest first, ties by id).
  int PassOrderBands = 0;
};

struct SURFACELODFILTERS_EXPORT ProvedCollapseStatistics
{
  long long Collapses = 0, Attempts = 0, Flips = 0;
  long long Rejected[3] = { 0, 0, 0 }; // collapses rejected by topology, output -> input, input -> output
  long long BorderGuardRejections = 0; // border collapses refused for their star (valence, slivers)
  // New triangles whose facing test and proof ran, and those answered from an earlier try of the
  // same triangle (each is decided once per run: its answer depends on its corners only).
  long long NewTriangleProofs = 0, NewTrianglesRecalled = 0;
  long long NewTrianglesCarried = 0; // ... and those answered from an earlier call (CarriedProofs)
  // Gatherings of the input triangles near a change (a BVH walk, then each one's sphere test
  // against the replaced triangles) and of the unchanged output around it (ReuseStarGathering).
  long long InputGatherings = 0, OutputGatherings = 0;
  // Input triangles near a change left out because their witness stays (Witnesses), changes
  // accepted by new witnesses alone (no local output, no proof), and the output triangles gathered
  // into the local outputs of the proofs (their BVHs are built per try: the work that grew with
  // the tolerance over the output's size).
  long long WitnessesKept = 0, AcceptedByWitnesses = 0, LocalOutputTriangles = 0;
  // Input triangles examined to find those relying on each change (a gathering's, or the index's).
  long long InputTrianglesGathered = 0;
  // The new triangles' verdicts in the table at the end, and those dropped from it (a corner had
  // been removed) when it would have grown: its size follows the live verdicts, not every try.
  long long VerdictsHeld = 0, VerdictsDropped = 0;
  // The collapse passes' walk: the distances between consecutive vertices visited, summed, and
  // their number (PassOrderBands shortens the steps: the memory read per try is nearby).
  double PassStepLength = 0;
  long long PassSteps = 0;
  // Walks of an output vertex's references to count its triangles (one per vertex on entry, then
  // one per corner of the triangles each accepted change gathered): the tries read the counts
  // from a per-vertex array instead, so the walks follow the changes, not the tries.
  long long DegreeWalks = 0;
  int Rounds = 0;
  bool TargetReached = false; // parameters.TargetTriangles was met (the passes stopped there)
  bool WorkBoundReached = false; // parameters.MaximumProofPieces stopped the passes
};

// Simplifies `triangles` (3 vertex ids of `input` each; `patches` one id per triangle, kept for the
// surviving triangles) in place. The output must be within epsilon of the input both ways on entry.
// Returns false when aborted (the triangles are then still valid and within the bound).
SURFACELODFILTERS_EXPORT bool ProvedCollapses(const TriangleMesh& input, const TriangleBVH& inputBvh,
  const ProvedCollapseParameters& parameters, std::vector<Index>& triangles, std::vector<Index>& patches,
  ProvedCollapseStatistics& statistics, const ProgressFunction& progress = nullptr,
  long long* proofPieces = nullptr);
} // namespace slod

#endif
