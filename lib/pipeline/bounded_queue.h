#pragma once
/// @file
/// BoundedQueue<T>: a blocking FIFO with a capacity (back-pressure on the producer).

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <utility>

#include "core/check.h"

namespace mvtrack::pipeline {

/// A FIFO holding at most `capacity` items. Push waits while it is full (back-pressure: the
/// producer slows down, nothing is dropped); Pop waits while it is empty.
///
/// Thread safety: every method is thread-safe (any number of producers and consumers).
/// Shutdown: Close() wakes every waiter; Push then returns false, Pop drains what is queued
/// and then returns nullopt.
template <typename T>
class BoundedQueue {
 public:
  /// `capacity` >= 1 (checked).
  explicit BoundedQueue(std::size_t capacity) : capacity_(capacity) {
    MVTRACK_CHECK_MSG(capacity >= 1, "BoundedQueue capacity must be >= 1");
  }

  /// Appends `item`, waiting while the queue is full. Returns false (item discarded) once
  /// closed.
  bool Push(T item) {
    {
      std::unique_lock<std::mutex> lock(mu_);
      space_cv_.wait(lock, [&] { return closed_ || items_.size() < capacity_; });
      if (closed_) return false;
      items_.push_back(std::move(item));
    }
    item_cv_.notify_one();
    return true;
  }

  /// Removes the oldest item, waiting while the queue is empty; nullopt once closed and empty.
  std::optional<T> Pop() {
    std::optional<T> out;
    {
      std::unique_lock<std::mutex> lock(mu_);
      item_cv_.wait(lock, [&] { return closed_ || !items_.empty(); });
      if (items_.empty()) return std::nullopt;
      out.emplace(std::move(items_.front()));
      items_.pop_front();
    }
    space_cv_.notify_one();
    return out;
  }

  /// Closes the queue (idempotent).
  void Close() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      closed_ = true;
    }
    item_cv_.notify_all();
    space_cv_.notify_all();
  }

  /// Items waiting.
  std::size_t size() const {
    std::lock_guard<std::mutex> lock(mu_);
    return items_.size();
  }

  /// The capacity.
  std::size_t capacity() const { return capacity_; }

 private:
  const std::size_t capacity_;
  mutable std::mutex mu_;
  std::condition_variable item_cv_;
  std::condition_variable space_cv_;
  std::deque<T> items_;
  bool closed_ = false;
};

}  // namespace mvtrack::pipeline
