// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: an addressable binary min-heap over dense element ids.
//
// Collapse algorithms keep one cost per element (edge, triangle) and change a few of them after
// every collapse. An addressable heap updates a key in place (sift up or down) instead of pushing
// a new entry and skipping stale ones later, so the heap never grows beyond the element count and
// no version stamps are needed. Two flat arrays: Heap[slot] = {key, id} (the key is stored inline
// so that sifting touches one cache line per level), Slot[id] = slot (-1 when absent).
// Ties are broken by id, which makes the order, and so every algorithm using it, deterministic.
//
// Lower() supports lazy increases: a caller that only lowers keys in place and keeps the true
// cost elsewhere re-keys an element when it reaches the top (ResetTop) - most raised costs are
// raised again before they surface, so the expensive sift-downs mostly never happen.
#ifndef slodIndexedHeap_h
#define slodIndexedHeap_h

#include "slodTriangleMesh.h"

#include <vector>

namespace slod
{
template <typename Key = float>
class IndexedHeap
{
public:
  // Room for ids 0..n-1, all absent.
  void Reset(Index n)
  {
    this->Slot.assign(size_t(n), InvalidIndex);
    this->Heap.clear();
    this->Heap.reserve(size_t(n));
  }

  // Empties the heap in time proportional to its size, keeping room for the same ids: for callers
  // that run many small searches (a Dijkstra region, an ear clipping) over one large id range.
  void Clear()
  {
    for (const Entry& e : this->Heap)
    {
      this->Slot[e.Id] = InvalidIndex;
    }
    this->Heap.clear();
  }

  // Room for at least ids 0..n-1, keeping the current entries.
  void Reserve(Index n)
  {
    if (this->Slot.size() < size_t(n))
    {
      this->Slot.resize(size_t(n), InvalidIndex);
    }
  }

  // Sets every key at once and heapifies in linear time (ids with a negative key stay absent).
  void Build(const Key* keys, Index n)
  {
    this->Slot.assign(size_t(n), InvalidIndex);
    this->Heap.clear();
    this->Heap.reserve(size_t(n));
    for (Index id = 0; id < n; ++id)
    {
      if (!(keys[id] < Key(0)))
      {
        this->Slot[id] = static_cast<Index>(this->Heap.size());
        this->Heap.push_back({ keys[id], id });
      }
    }
    for (Index s = static_cast<Index>(this->Heap.size()) / 2 - 1; s >= 0; --s)
    {
      this->SiftDown(s);
    }
  }

  bool Empty() const { return this->Heap.empty(); }
  Index Size() const { return static_cast<Index>(this->Heap.size()); }
  bool Contains(Index id) const { return this->Slot[id] != InvalidIndex; }
  Key GetKey(Index id) const { return this->Heap[this->Slot[id]].K; }
  Index Top() const { return this->Heap.front().Id; }
  Key TopKey() const { return this->Heap.front().K; }

  // Inserts id or changes its key.
  void Set(Index id, Key key)
  {
    const Index s = this->Slot[id];
    if (s == InvalidIndex)
    {
      this->Insert(id, key);
      return;
    }
    const Key old = this->Heap[s].K;
    this->Heap[s].K = key;
    if (key < old)
    {
      this->SiftUp(s);
    }
    else
    {
      this->SiftDown(s);
    }
  }

  // Inserts id, or lowers its key; a higher key is ignored (see the lazy-increase note above).
  void Lower(Index id, Key key)
  {
    const Index s = this->Slot[id];
    if (s == InvalidIndex)
    {
      this->Insert(id, key);
    }
    else if (key < this->Heap[s].K)
    {
      this->Heap[s].K = key;
      this->SiftUp(s);
    }
  }

  // Gives the top element a new (higher) key.
  void ResetTop(Key key)
  {
    this->Heap.front().K = key;
    this->SiftDown(0);
  }

  void Remove(Index id)
  {
    const Index s = this->Slot[id];
    if (s == InvalidIndex)
    {
      return;
    }
    const Entry last = this->Heap.back();
    this->Heap.pop_back();
    this->Slot[id] = InvalidIndex;
    if (last.Id != id)
    {
      this->Heap[s] = last;
      this->Slot[last.Id] = s;
      this->SiftUp(s);
      this->SiftDown(this->Slot[last.Id]);
    }
  }

  Index Pop()
  {
    const Index id = this->Heap.front().Id;
    this->Remove(id);
    return id;
  }

  size_t MemoryBytes() const { return this->Heap.capacity() * sizeof(Entry) + this->Slot.capacity() * sizeof(Index); }

private:
  struct Entry
  {
    Key K;
    Index Id;
  };
  static bool Less(const Entry& a, const Entry& b) { return a.K < b.K || (!(b.K < a.K) && a.Id < b.Id); }
  void Insert(Index id, Key key)
  {
    this->Slot[id] = static_cast<Index>(this->Heap.size());
    this->Heap.push_back({ key, id });
    this->SiftUp(this->Slot[id]);
  }
  void SiftUp(Index s)
  {
    const Entry e = this->Heap[s];
    while (s > 0)
    {
      const Index parent = (s - 1) / 2;
      if (!Less(e, this->Heap[parent]))
      {
        break;
      }
      this->Heap[s] = this->Heap[parent];
      this->Slot[this->Heap[s].Id] = s;
      s = parent;
    }
    this->Heap[s] = e;
    this->Slot[e.Id] = s;
  }
  void SiftDown(Index s)
  {
    const Index n = static_cast<Index>(this->Heap.size());
    const Entry e = this->Heap[s];
    for (;;)
    {
      Index child = 2 * s + 1;
      if (child >= n)
      {
        break;
      }
      if (child + 1 < n && Less(this->Heap[child + 1], this->Heap[child]))
      {
        ++child;
      }
      if (!Less(this->Heap[child], e))
      {
        break;
      }
      this->Heap[s] = this->Heap[child];
      this->Slot[this->Heap[s].Id] = s;
      s = child;
    }
    this->Heap[s] = e;
    this->Slot[e.Id] = s;
  }

  std::vector<Entry> Heap;
  std::vector<Index> Slot;
};
} // namespace slod

#endif
