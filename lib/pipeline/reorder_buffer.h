#pragma once
/// @file
/// SequenceReorderBuffer<T>: turns items produced out of order by several threads back into
/// their sequence order (0, 1, 2, ...), with a bounded look-ahead.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <utility>

#include "core/check.h"

namespace mvtrack::pipeline {

/// Producers insert items tagged with their sequence number (each number exactly once, any
/// order); the consumer pops them strictly in sequence order, so what it sees never depends on
/// producer timing. Look-ahead bound: an item more than `capacity` - 1 ahead of the next
/// expected one waits for room (unless inserted with wait_for_room = false); the next expected
/// item always fits, so producers whose items are each in sequence order cannot deadlock.
///
/// Thread safety: every method is thread-safe (many producers, one consumer). No shutdown
/// protocol of its own: the pipeline ends the sequence with a sentinel item.
template <typename T>
class SequenceReorderBuffer {
 public:
  /// `capacity` >= 1 (checked); the first expected sequence number is `first`.
  explicit SequenceReorderBuffer(std::size_t capacity, std::uint64_t first = 0)
      : capacity_(capacity), next_(first) {
    MVTRACK_CHECK_MSG(capacity >= 1, "SequenceReorderBuffer capacity must be >= 1");
  }

  /// Inserts item `seq`, which must not have been inserted before and be >= the next expected
  /// number (checked). With `wait_for_room`, waits while seq >= next + capacity.
  void Insert(std::uint64_t seq, T item, bool wait_for_room = true) {
    {
      std::unique_lock<std::mutex> lock(mu_);
      if (wait_for_room) room_cv_.wait(lock, [&] { return seq < next_ + capacity_; });
      MVTRACK_CHECK_MSG(seq >= next_, "sequence number already consumed");
      const bool inserted = items_.emplace(seq, std::move(item)).second;
      MVTRACK_CHECK_MSG(inserted, "sequence number inserted twice");
      if (seq != next_) return;  // the consumer only waits for next_
    }
    ready_cv_.notify_all();
  }

  /// Waits for the next item in sequence order, removes and returns it.
  T PopNext() {
    std::unique_lock<std::mutex> lock(mu_);
    ready_cv_.wait(lock, [&] { return !items_.empty() && items_.begin()->first == next_; });
    auto node = items_.extract(items_.begin());
    ++next_;
    lock.unlock();
    room_cv_.notify_all();
    return std::move(node.mapped());
  }

  /// Items buffered (inserted, not yet popped).
  std::size_t size() const {
    std::lock_guard<std::mutex> lock(mu_);
    return items_.size();
  }

  /// The next sequence number PopNext returns.
  std::uint64_t next() const {
    std::lock_guard<std::mutex> lock(mu_);
    return next_;
  }

 private:
  const std::size_t capacity_;
  mutable std::mutex mu_;
  std::condition_variable ready_cv_;  // the next expected item arrived
  std::condition_variable room_cv_;   // next_ advanced
  std::map<std::uint64_t, T> items_;
  std::uint64_t next_;
};

}  // namespace mvtrack::pipeline
