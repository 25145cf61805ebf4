#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

namespace agv::pipeline {

enum class QueuePolicy {
  kBlock,       // push waits (up to its timeout) for room
  kDropOldest,  // push never waits: when full, the oldest item is dropped and counted
};

struct QueueStats {
  std::uint64_t pushed = 0;      // items accepted
  std::uint64_t popped = 0;      // items handed to a consumer
  std::uint64_t dropped = 0;     // oldest items discarded to make room (kDropOldest)
  std::uint64_t superseded = 0;  // items skipped by pop_newest because a newer one was there
  std::uint64_t rejected = 0;    // pushes refused: timed out (kBlock) or queue closed
  std::size_t max_depth = 0;
};

// A thread-safe FIFO of bounded capacity (after Cartographer's BlockingQueue). Every item pushed
// is accounted for: pushed = popped + dropped + superseded + size(). close() wakes every waiter;
// after it, pushes are refused and pops drain what is left, then return nullopt.
template <typename T>
class BoundedQueue {
 public:
  using Clock = std::chrono::steady_clock;

  BoundedQueue(std::size_t capacity, QueuePolicy policy)
      : capacity_(capacity > 0 ? capacity : 1), policy_(policy) {}

  // True when the item was queued.
  bool push(T item, std::chrono::nanoseconds timeout = std::chrono::hours(24)) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (policy_ == QueuePolicy::kBlock) {
      const bool room = not_full_.wait_for(lock, timeout,
                                           [this] { return closed_ || items_.size() < capacity_; });
      if (!room || closed_) {
        ++stats_.rejected;
        return false;
      }
    } else {
      if (closed_) {
        ++stats_.rejected;
        return false;
      }
      if (items_.size() >= capacity_) {
        items_.pop_front();
        ++stats_.dropped;
      }
    }
    items_.push_back(std::move(item));
    ++stats_.pushed;
    if (items_.size() > stats_.max_depth) stats_.max_depth = items_.size();
    not_empty_.notify_one();
    return true;
  }

  // The oldest item, waiting up to `timeout` for one; nullopt on timeout or when closed and empty.
  std::optional<T> pop(std::chrono::nanoseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_empty_.wait_for(lock, timeout, [this] { return closed_ || !items_.empty(); });
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    ++stats_.popped;
    not_full_.notify_one();
    return item;
  }

  // The newest item without waiting (nullopt when empty); older ones are discarded as superseded.
  std::optional<T> pop_newest() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (items_.empty()) return std::nullopt;
    stats_.superseded += items_.size() - 1;
    T item = std::move(items_.back());
    items_.clear();
    ++stats_.popped;
    not_full_.notify_all();
    return item;
  }

  void close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    not_full_.notify_all();
    not_empty_.notify_all();
  }

  bool closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
  }
  std::size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size();
  }
  std::size_t capacity() const { return capacity_; }
  QueuePolicy policy() const { return policy_; }
  QueueStats stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return stats_;
  }

 private:
  const std::size_t capacity_;
  const QueuePolicy policy_;
  mutable std::mutex mutex_;
  std::condition_variable not_full_, not_empty_;
  std::deque<T> items_;
  QueueStats stats_;
  bool closed_ = false;
};

}  // namespace agv::pipeline
