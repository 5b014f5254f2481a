// FlatKeyMap: a map from 64-bit keys to small values in one open-addressed array (linear probing),
// for the spacing pipeline's lattice samples and corner ids. std::unordered_map allocates a node per
// entry and chases a pointer per lookup; on 30P30N's background tree (hundreds of thousands of lattice
// points, a dozen lookups each) that bookkeeping cost as much as the serial part of evaluating eq. 3.6.
// No iteration over the entries is offered: callers keep their own ordered key lists, so nothing can
// depend on the table's layout (the values a caller computes stay bit-identical).
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/mix64.hpp"

namespace pdmesh {

template <class V>
class FlatKeyMap {
 public:
  // One key cannot be stored: it marks an empty slot (lattice keys never reach it).
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  FlatKeyMap() { rehash(16); }

  std::size_t size() const { return size_; }

  // Makes room for n entries in all without rehashing on the way.
  void reserve(std::size_t n) {
    if (2 * n > slots_.size()) rehash(2 * n);
  }

  // A hint that key is about to be looked up or inserted: fetches the cache line of its first slot.
  // Changes nothing in the table (a rehash before the lookup only wastes the fetch).
  void prefetch(std::uint64_t key) const { __builtin_prefetch(&slots_[slot(key)]); }

  // Inserts (key, value) if key is absent. Returns the entry's value and whether it was inserted. The
  // pointer is valid until the next insertion.
  std::pair<V*, bool> try_emplace(std::uint64_t key, const V& value) {
    if (key == kEmpty) throw std::invalid_argument("FlatKeyMap: the reserved key");
    if (2 * (size_ + 1) > slots_.size()) rehash(2 * slots_.size());
    std::size_t i = slot(key);
    while (slots_[i].key != kEmpty) {
      if (slots_[i].key == key) return {&slots_[i].value, false};
      i = (i + 1) & mask_;
    }
    slots_[i].key = key;
    slots_[i].value = value;
    ++size_;
    return {&slots_[i].value, true};
  }

  // The value of key, or nullptr when absent.
  const V* find(std::uint64_t key) const {
    std::size_t i = slot(key);
    while (slots_[i].key != kEmpty) {
      if (slots_[i].key == key) return &slots_[i].value;
      i = (i + 1) & mask_;
    }
    return nullptr;
  }
  V* find(std::uint64_t key) { return const_cast<V*>(static_cast<const FlatKeyMap&>(*this).find(key)); }

  // The value of key; throws std::out_of_range when absent (as std::unordered_map::at).
  const V& at(std::uint64_t key) const {
    const V* v = find(key);
    if (!v) throw std::out_of_range("FlatKeyMap::at: no such key");
    return *v;
  }
  V& at(std::uint64_t key) { return const_cast<V&>(static_cast<const FlatKeyMap&>(*this).at(key)); }

 private:
  struct Slot {
    std::uint64_t key = kEmpty;
    V value{};
  };

  // Keys differ in few low bits of each half: index by their mix.
  std::size_t slot(std::uint64_t k) const { return static_cast<std::size_t>(mix64(k)) & mask_; }

  void rehash(std::size_t at_least) {
    std::size_t capacity = 16;
    while (capacity < at_least) capacity *= 2;
    std::vector<Slot> old(capacity);
    old.swap(slots_);
    mask_ = capacity - 1;
    for (const Slot& s : old) {
      if (s.key == kEmpty) continue;
      std::size_t i = slot(s.key);
      while (slots_[i].key != kEmpty) i = (i + 1) & mask_;
      slots_[i] = s;
    }
  }

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
};

}  // namespace pdmesh
