#pragma once
/// \file A bounded, thread-safe store of results keyed by the bytes of everything they were
/// computed from, for stages that the resolve loop runs again on a model that changed in a few
/// places (OutlineMemo, KerfMemo). A result is reused only where its inputs are the same to the
/// bit, so a stage gives the same output with or without one.
#include <cstddef>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

namespace kerfab {

/// \p Value tells what it holds in `std::size_t bytes() const`. The store keeps at most
/// `max_bytes` of keys and values and is emptied when an insert would pass that.
template <class Value>
class Memo {
 public:
  explicit Memo(std::size_t max_bytes) : max_bytes_(max_bytes) {}

  std::optional<Value> find(const std::string& key) const {
    const std::lock_guard lock(mutex_);
    const auto it = values_.find(key);
    if (it == values_.end()) {
      ++misses_;
      return std::nullopt;
    }
    ++hits_;
    return it->second;
  }

  void insert(std::string key, Value value) {
    const std::size_t bytes = key.size() + value.bytes();
    if (bytes > max_bytes_) return;
    const std::lock_guard lock(mutex_);
    if (bytes_ + bytes > max_bytes_) values_.clear(), bytes_ = 0;
    if (values_.emplace(std::move(key), std::move(value)).second) bytes_ += bytes;
  }

  std::size_t hits() const {
    const std::lock_guard lock(mutex_);
    return hits_;
  }

  std::size_t misses() const {
    const std::lock_guard lock(mutex_);
    return misses_;
  }

 private:
  mutable std::mutex mutex_;
  std::unordered_map<std::string, Value> values_;
  std::size_t max_bytes_, bytes_ = 0;
  mutable std::size_t hits_ = 0, misses_ = 0;
};

}  // namespace kerfab
