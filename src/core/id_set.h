// A set of ids (map ids, edge keys: any int64 but kNoId) that keeps its memory from one use
// to the next.
#pragma once

#include <cstddef>
#include <vector>

#include "core/map.h"

namespace plslam {

/// Open addressing with linear probing in one array. The tracker fills sets of landmark ids
/// on every frame (the local map's landmarks, the ones already matched); node-based sets
/// allocate one node per id, and those allocations slowed down as the heap aged over a long
/// run (docs/RESULTS.md, "The long run's growing search"). kNoId is never a member.
class IdSet {
 public:
  /// Empties the set, keeping room for `expected` ids before it has to grow.
  void clear(size_t expected = 0);
  /// Adds `id`; false when it was there already (or is kNoId).
  bool insert(Id id);
  bool contains(Id id) const;
  size_t size() const { return size_; }

 private:
  size_t slotOf(Id id) const;  // where `id` is, or the free slot where it would go
  void grow();

  std::vector<Id> slots_;  // kNoId where free; a power of two long, at most half full
  size_t size_ = 0;
};

}  // namespace plslam
