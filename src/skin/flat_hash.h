#pragma once
/// A small open-addressing hash map from 64-bit keys to trivially copyable values, for the
/// per-frame grid caches of the marching cubes (std::unordered_map allocates a node per
/// entry; this one reuses one array from frame to frame).
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace viscera::skin {

template <typename Value>
class FlatHashMap {
 public:
  static constexpr uint64_t kEmpty = ~uint64_t{0};

  /// Removes all entries, keeping the capacity.
  void Clear() {
    if (size_ == 0) return;
    std::fill(keys_.begin(), keys_.end(), kEmpty);
    size_ = 0;
  }

  size_t size() const { return size_; }

  /// Value for key, or null. @pre key != kEmpty.
  Value* Find(uint64_t key) {
    return const_cast<Value*>(static_cast<const FlatHashMap*>(this)->Find(key));
  }
  const Value* Find(uint64_t key) const {
    if (keys_.empty()) return nullptr;
    for (size_t i = Slot(key);; i = (i + 1) & mask_) {
      if (keys_[i] == key) return &values_[i];
      if (keys_[i] == kEmpty) return nullptr;
    }
  }

  /// Inserts `init` under key if absent. Returns the value and whether it was inserted.
  /// Pointers stay valid until the next insertion. @pre key != kEmpty.
  std::pair<Value*, bool> Insert(uint64_t key, const Value& init) {
    if (2 * (size_ + 1) > keys_.size()) Grow();
    for (size_t i = Slot(key);; i = (i + 1) & mask_) {
      if (keys_[i] == key) return {&values_[i], false};
      if (keys_[i] == kEmpty) {
        keys_[i] = key;
        values_[i] = init;
        ++size_;
        return {&values_[i], true};
      }
    }
  }

 private:
  size_t Slot(uint64_t key) const {
    // splitmix64 finalizer: grid keys are highly regular
    key ^= key >> 30;
    key *= 0xbf58476d1ce4e5b9ull;
    key ^= key >> 27;
    key *= 0x94d049bb133111ebull;
    key ^= key >> 31;
    return static_cast<size_t>(key) & mask_;
  }

  void Grow() {
    std::vector<uint64_t> old_keys = std::move(keys_);
    std::vector<Value> old_values = std::move(values_);
    const size_t capacity = old_keys.empty() ? 1024 : 2 * old_keys.size();
    keys_.assign(capacity, kEmpty);
    values_.resize(capacity);
    mask_ = capacity - 1;
    size_ = 0;
    for (size_t i = 0; i < old_keys.size(); ++i) {
      if (old_keys[i] != kEmpty) Insert(old_keys[i], old_values[i]);
    }
  }

  std::vector<uint64_t> keys_;
  std::vector<Value> values_;
  size_t mask_ = 0;
  size_t size_ = 0;
};

}  // namespace viscera::skin
