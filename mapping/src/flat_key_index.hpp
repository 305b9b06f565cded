#pragma once
// A flat, open-addressing index of OctoMap keys: each distinct key gets the next number, in the
// order keys first arrive. The semantic map's insertion asks it hundreds of thousands of times per
// frame (every cell of every ray); std::unordered_set (octomap::KeySet) spent most of a frame on
// node allocation and pointer chasing there. Capacity grows by doubling and is kept between frames.
#include <cstdint>
#include <utility>
#include <vector>

#include <octomap/OcTreeKey.h>

namespace navaid::mapping {

class FlatKeyIndex {
 public:
  static std::uint64_t pack(const octomap::OcTreeKey& k) {
    return static_cast<std::uint64_t>(k[0]) | (static_cast<std::uint64_t>(k[1]) << 16) |
           (static_cast<std::uint64_t>(k[2]) << 32);
  }
  static octomap::OcTreeKey unpack(std::uint64_t p) {
    return octomap::OcTreeKey(static_cast<octomap::key_type>(p & 0xFFFF), static_cast<octomap::key_type>((p >> 16) & 0xFFFF),
                              static_cast<octomap::key_type>((p >> 32) & 0xFFFF));
  }

  /// Empties the index, keeping its memory. Keys leave in reverse order of arrival: each key's probe
  /// run then holds only earlier keys, still present, so slot_of() finds it.
  void clear() {
    for (auto k = keys_.rbegin(); k != keys_.rend(); ++k) slots_[slot_of(*k)] = kEmpty;
    keys_.clear();
  }

  /// The number of `key`, and whether it was new.
  std::pair<std::uint32_t, bool> insert(std::uint64_t key) {
    if (2 * (keys_.size() + 1) > slots_.size()) grow();
    std::size_t s = hash(key) & mask_;
    while (slots_[s] != kEmpty) {
      if (keys_[slots_[s]] == key) return {slots_[s], false};
      s = (s + 1) & mask_;
    }
    slots_[s] = static_cast<std::uint32_t>(keys_.size());
    keys_.push_back(key);
    return {slots_[s], true};
  }

  bool contains(std::uint64_t key) const {
    if (slots_.empty()) return false;
    for (std::size_t s = hash(key) & mask_; slots_[s] != kEmpty; s = (s + 1) & mask_)
      if (keys_[slots_[s]] == key) return true;
    return false;
  }

  std::size_t size() const { return keys_.size(); }
  /// Keys by number (first-arrival order).
  const std::vector<std::uint64_t>& keys() const { return keys_; }

 private:
  static constexpr std::uint32_t kEmpty = ~std::uint32_t{0};
  static std::size_t hash(std::uint64_t k) {
    k ^= k >> 29;  // a multiplicative mix: neighbouring cells spread over the table
    k *= 0xBF58476D1CE4E5B9ULL;
    return static_cast<std::size_t>(k ^ (k >> 32));
  }
  std::size_t slot_of(std::uint64_t key) const {
    std::size_t s = hash(key) & mask_;
    while (keys_[slots_[s]] != key) s = (s + 1) & mask_;
    return s;
  }
  void grow() {
    const std::size_t capacity = slots_.empty() ? 1024 : 2 * slots_.size();
    slots_.assign(capacity, kEmpty);
    mask_ = capacity - 1;
    for (std::uint32_t i = 0; i < keys_.size(); ++i) {
      std::size_t s = hash(keys_[i]) & mask_;
      while (slots_[s] != kEmpty) s = (s + 1) & mask_;
      slots_[s] = i;
    }
  }

  std::vector<std::uint32_t> slots_;  ///< number of the key stored there, kEmpty when free
  std::vector<std::uint64_t> keys_;
  std::size_t mask_ = 0;
};

}  // namespace navaid::mapping
