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
/// Wake-ups are targeted: a producer waiting for room waits on its own condition variable,
/// registered under its sequence number, and PopNext wakes only the producer whose item has just
/// become admissible (one per pop; with 32 camera threads waiting, waking them all cost about
/// 1,000 context switches per frame, issue 44); an insert wakes the consumer only when it
/// brings the next expected item.
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
      if (wait_for_room && seq >= next_ + capacity_) {
        // Each sequence number is inserted once, so at most one producer waits for it.
        std::condition_variable room;
        const bool registered = waiting_.emplace(seq, &room).second;
        MVTRACK_CHECK_MSG(registered, "sequence number inserted twice");
        room.wait(lock, [&] { return seq < next_ + capacity_; });
        waiting_.erase(seq);
      }
      MVTRACK_CHECK_MSG(seq >= next_, "sequence number already consumed");
      const bool inserted = items_.emplace(seq, std::move(item)).second;
      MVTRACK_CHECK_MSG(inserted, "sequence number inserted twice");
      if (seq != next_) return;  // the consumer only waits for next_
    }
    ready_cv_.notify_one();  // one consumer
  }

  /// Waits for the next item in sequence order, removes and returns it.
  T PopNext() {
    std::unique_lock<std::mutex> lock(mu_);
    ready_cv_.wait(lock, [&] { return !items_.empty() && items_.begin()->first == next_; });
    auto node = items_.extract(items_.begin());
    ++next_;
    // The one number that became admissible; its producer's condition variable lives on the
    // producer's stack until it has seen the room, so it is notified under the lock.
    const auto waiter = waiting_.find(next_ + capacity_ - 1);
    if (waiter != waiting_.end()) waiter->second->notify_one();
    lock.unlock();
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
  std::condition_variable ready_cv_;                           // the next expected item arrived
  std::map<std::uint64_t, std::condition_variable*> waiting_;  // producers waiting for room
  std::map<std::uint64_t, T> items_;
  std::uint64_t next_;
};

}  // namespace mvtrack::pipeline
