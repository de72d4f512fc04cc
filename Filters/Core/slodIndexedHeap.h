// SurfaceLOD shared core: an addressable binary min-heap over dense element ids.
//
// Collapse algorithms keep one cost per element (edge, triangle) and change a few of them after
// every collapse. An addressable heap updates a key in place (sift up or down) instead of pushing
// a new entry and skipping stale ones later, so the heap never grows beyond the element count and
// no version stamps are needed. Three flat arrays: Keys[id], Heap[slot] = id, Slot[id] = slot
// (-1 when the id is not in the heap). Ties are broken by id, which makes the order, and so
// every algorithm using it, deterministic.
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
    this->Keys.assign(size_t(n), Key(0));
    this->Slot.assign(size_t(n), InvalidIndex);
    this->Heap.clear();
    this->Heap.reserve(size_t(n));
  }

  // Sets every key at once and heapifies in linear time (ids with a negative key stay absent).
  void Build(const Key* keys, Index n)
  {
    this->Keys.assign(keys, keys + n);
    this->Slot.assign(size_t(n), InvalidIndex);
    this->Heap.clear();
    for (Index id = 0; id < n; ++id)
    {
      if (!(keys[id] < Key(0)))
      {
        this->Slot[id] = static_cast<Index>(this->Heap.size());
        this->Heap.push_back(id);
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
  Key GetKey(Index id) const { return this->Keys[id]; }
  Index Top() const { return this->Heap.front(); }
  Key TopKey() const { return this->Keys[this->Heap.front()]; }

  // Inserts id or changes its key.
  void Set(Index id, Key key)
  {
    const Index s = this->Slot[id];
    this->Keys[id] = key;
    if (s == InvalidIndex)
    {
      this->Slot[id] = static_cast<Index>(this->Heap.size());
      this->Heap.push_back(id);
      this->SiftUp(this->Slot[id]);
    }
    else
    {
      this->SiftUp(s);
      this->SiftDown(this->Slot[id]);
    }
  }

  void Remove(Index id)
  {
    const Index s = this->Slot[id];
    if (s == InvalidIndex)
    {
      return;
    }
    const Index last = this->Heap.back();
    this->Heap.pop_back();
    this->Slot[id] = InvalidIndex;
    if (last != id)
    {
      this->Heap[s] = last;
      this->Slot[last] = s;
      this->SiftUp(s);
      this->SiftDown(this->Slot[last]);
    }
  }

  Index Pop()
  {
    const Index id = this->Heap.front();
    this->Remove(id);
    return id;
  }

  size_t MemoryBytes() const
  {
    return this->Keys.capacity() * sizeof(Key) + (this->Slot.capacity() + this->Heap.capacity()) * sizeof(Index);
  }

private:
  bool Less(Index a, Index b) const
  {
    return this->Keys[a] < this->Keys[b] || (!(this->Keys[b] < this->Keys[a]) && a < b);
  }
  void SiftUp(Index s)
  {
    const Index id = this->Heap[s];
    while (s > 0)
    {
      const Index parent = (s - 1) / 2;
      if (!this->Less(id, this->Heap[parent]))
      {
        break;
      }
      this->Heap[s] = this->Heap[parent];
      this->Slot[this->Heap[s]] = s;
      s = parent;
    }
    this->Heap[s] = id;
    this->Slot[id] = s;
  }
  void SiftDown(Index s)
  {
    const Index n = static_cast<Index>(this->Heap.size());
    const Index id = this->Heap[s];
    for (;;)
    {
      Index child = 2 * s + 1;
      if (child >= n)
      {
        break;
      }
      if (child + 1 < n && this->Less(this->Heap[child + 1], this->Heap[child]))
      {
        ++child;
      }
      if (!this->Less(this->Heap[child], id))
      {
        break;
      }
      this->Heap[s] = this->Heap[child];
      this->Slot[this->Heap[s]] = s;
      s = child;
    }
    this->Heap[s] = id;
    this->Slot[id] = s;
  }

  std::vector<Key> Keys;
  std::vector<Index> Heap;
  std::vector<Index> Slot;
};
} // namespace slod

#endif
