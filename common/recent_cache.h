#pragma once

#include <cstddef>
#include <deque>
#include <mutex>
#include <utility>

namespace agv {

// The values made for the last `capacity` keys, for things that are costly to make and the same
// for the same key (a camera's floor map, a floor texture tile). Thread-safe; a value is made
// outside the lock (two threads asking for a new key at once may both make it: the first kept
// wins), so Value should be cheap to copy (a shared pointer, a cv::Mat header).
template <typename Key, typename Value>
class RecentCache {
 public:
  explicit RecentCache(std::size_t capacity) : capacity_(capacity) {}

  template <typename Make>
  Value get(const Key& key, Make make) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& [k, value] : kept_)
        if (k == key) return value;
    }
    Value made = make();
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [k, value] : kept_)
      if (k == key) return value;
    kept_.emplace_back(key, made);
    if (kept_.size() > capacity_) kept_.pop_front();
    return made;
  }

 private:
  std::size_t capacity_;
  std::mutex mutex_;
  std::deque<std::pair<Key, Value>> kept_;
};

}  // namespace agv
