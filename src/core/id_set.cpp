#include "core/id_set.h"

#include <algorithm>
#include <cstdint>

namespace plslam {

namespace {

constexpr size_t kMinSlots = 64;

size_t slotsFor(size_t ids) {
  size_t n = kMinSlots;
  while (n < 2 * ids) n *= 2;
  return n;
}

}  // namespace

void IdSet::clear(size_t expected) {
  const size_t wanted = slotsFor(expected);
  if (slots_.size() < wanted) slots_.assign(wanted, kNoId);
  else std::fill(slots_.begin(), slots_.end(), kNoId);
  size_ = 0;
}

size_t IdSet::slotOf(Id id) const {
  // Ids are consecutive integers: Fibonacci hashing (the product's top bits) spreads
  // neighbours over the table.
  const size_t mask = slots_.size() - 1;
  const int bits = __builtin_ctzll(slots_.size());
  size_t i = static_cast<size_t>((static_cast<uint64_t>(id) * 0x9E3779B97F4A7C15ull) >> (64 - bits));
  while (slots_[i] != kNoId && slots_[i] != id) i = (i + 1) & mask;
  return i;
}

bool IdSet::insert(Id id) {
  if (id == kNoId) return false;
  if (slots_.empty()) clear();
  size_t i = slotOf(id);
  if (slots_[i] == id) return false;
  if (2 * (size_ + 1) > slots_.size()) {
    grow();
    i = slotOf(id);
  }
  slots_[i] = id;
  ++size_;
  return true;
}

bool IdSet::contains(Id id) const {
  return id != kNoId && !slots_.empty() && slots_[slotOf(id)] == id;
}

void IdSet::grow() {
  std::vector<Id> old(2 * slots_.size(), kNoId);
  old.swap(slots_);
  for (Id id : old)
    if (id != kNoId) slots_[slotOf(id)] = id;
}

}  // namespace plslam
