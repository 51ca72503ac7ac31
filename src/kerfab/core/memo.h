#pragma once
/// \file A bounded, thread-safe store of results keyed by the bytes of everything they were
/// computed from, for stages that the resolve loop runs again on a model that changed in a few
/// places (OutlineMemo, KerfMemo). A result is reused only where its inputs are the same to the
/// bit, so a stage gives the same output with or without one.
#include <cstddef>
#include <list>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

namespace kerfab {

/// \p Value tells what it holds in `std::size_t bytes() const`. The store keeps at most
/// `max_bytes` of keys and values, the most recently used: when an insert would pass that, the
/// results used longest ago go. So what the last rebuild used stays while a rebuild's results
/// fit, where emptying the whole store when full dropped it: at 4000 mm Spot's outlines (about
/// 100 kB each) filled a 48 MB store twice in one rebuild, and the next rebuild found 5 of 1791.
template <class Value>
class Memo {
 public:
  explicit Memo(std::size_t max_bytes) : max_bytes_(max_bytes) {}

  std::optional<Value> find(const std::string& key) const {
    const std::lock_guard lock(mutex_);
    const auto it = index_.find(std::string_view(key));
    if (it == index_.end()) {
      ++misses_;
      return std::nullopt;
    }
    ++hits_;
    used_.splice(used_.begin(), used_, it->second);
    return it->second->value;
  }

  void insert(std::string key, Value value) {
    const std::size_t bytes = key.size() + value.bytes();
    if (bytes > max_bytes_) return;
    const std::lock_guard lock(mutex_);
    if (index_.contains(std::string_view(key))) return;
    used_.push_front(Entry{std::move(key), std::move(value), bytes});
    index_.emplace(std::string_view(used_.front().key), used_.begin());
    bytes_ += bytes;
    while (bytes_ > max_bytes_) {
      bytes_ -= used_.back().bytes;
      index_.erase(std::string_view(used_.back().key));
      used_.pop_back();
    }
  }

  std::size_t hits() const {
    const std::lock_guard lock(mutex_);
    return hits_;
  }

  std::size_t misses() const {
    const std::lock_guard lock(mutex_);
    return misses_;
  }

  /// Keys and values held [bytes].
  std::size_t bytes() const {
    const std::lock_guard lock(mutex_);
    return bytes_;
  }

 private:
  struct Entry {
    std::string key;
    Value value;
    std::size_t bytes;
  };
  mutable std::mutex mutex_;
  mutable std::list<Entry> used_;  // most recently used first
  /// Views of the keys in used_ (a list's elements stay where they are).
  std::unordered_map<std::string_view, typename std::list<Entry>::iterator> index_;
  std::size_t max_bytes_, bytes_ = 0;
  mutable std::size_t hits_ = 0, misses_ = 0;
};

}  // namespace kerfab
