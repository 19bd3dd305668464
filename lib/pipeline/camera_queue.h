#pragma once
/// @file
/// CameraQueue: the bounded input queue of one camera thread, with a stated overflow policy.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

#include "core/detection.h"
#include "tracker/frame_gate.h"

namespace mvtrack::pipeline {

/// What a full camera queue does with a new camera-frame.
enum class OverflowPolicy {
  /// Live use: the push never blocks. The oldest waiting camera-frame that still has its
  /// detections loses them (marked dropped, counted); its header (frame, utime, sequence
  /// position, frame events) stays queued, so frame sequencing is unaffected and the camera
  /// simply has no detections for that frame.
  kDropOldest,
  /// Replay and tests: the push waits until the camera thread has taken an item (lossless
  /// back-pressure on the submitter).
  kBlock,
};

/// Human-readable name of a policy ("drop_oldest", "block").
const char* ToString(OverflowPolicy policy);

/// One admitted camera-frame waiting for its camera thread.
struct CameraWork {
  std::uint64_t seq = 0;          ///< position in the pipeline's input sequence
  tracker::FrameEvents events;    ///< the FrameGate's decisions for it
  std::int64_t stream_epoch = 0;  ///< the FrameGate's stream epoch for it
  core::CameraFrame frame;        ///< detections emptied when dropped
  bool dropped = false;           ///< overflow: detections discarded, header kept
};

/// Wakes one waiting camera worker when any of its cameras' queues receives work or closes
/// (pipeline::Pipeline's camera workers each serve several cameras). No wake-up is lost: a
/// Notify() between a worker's last look at its queues and its Wait() makes that Wait() return
/// at once. Thread-safe.
class WorkSignal {
 public:
  /// Marks work as pending and wakes the worker if it waits.
  void Notify();
  /// Returns once work is pending (at once if it already is) and clears the mark.
  void Wait();

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  bool pending_ = false;
  bool waiting_ = false;
};

/// A FIFO of CameraWork holding at most `capacity` items with detections (dropped headers do
/// not count: they are a few bytes and are consumed without work). Items leave in push order.
///
/// Thread safety: every method is thread-safe (one producer and one consumer in the pipeline).
/// Shutdown: Close() wakes every waiter; Push then returns false, Pop drains what is queued
/// and then returns nullopt.
class CameraQueue {
 public:
  /// `capacity` >= 1 (checked). `signal` (optional, must outlive the queue) is notified after
  /// every push and on Close.
  CameraQueue(int capacity, OverflowPolicy policy, WorkSignal* signal = nullptr);

  /// Appends `work` (whose `dropped` must be false) with the queue's overflow policy. Returns
  /// false, and queues nothing, once closed.
  bool Push(CameraWork work);
  /// Waits for the oldest item and removes it; nullopt once closed and empty.
  std::optional<CameraWork> Pop();
  /// The oldest item's sequence number without waiting; nullopt when empty.
  std::optional<std::uint64_t> FrontSeq() const;
  /// Removes the oldest item without waiting; nullopt when empty.
  std::optional<CameraWork> TryPop();
  /// Closed and empty: nothing will come any more.
  bool Finished() const;
  /// Closes the queue (idempotent).
  void Close();

  /// Items with detections waiting (at most capacity(); dropped headers, consumed without
  /// work, are not counted: status reports depth against capacity).
  std::size_t depth() const;
  /// Camera-frames that lost their detections to overflow so far.
  std::int64_t dropped() const;
  /// The bound on waiting items with detections.
  int capacity() const { return capacity_; }
  /// The overflow policy.
  OverflowPolicy policy() const { return policy_; }

 private:
  const int capacity_;
  const OverflowPolicy policy_;
  WorkSignal* const signal_;
  mutable std::mutex mu_;
  std::condition_variable item_cv_;   // an item was pushed, or closed
  std::condition_variable space_cv_;  // an item with detections left, or closed
  std::deque<CameraWork> items_;
  // The dropped items always form a prefix of items_ (drops hit the oldest undropped item).
  std::size_t dropped_prefix_ = 0;
  std::int64_t dropped_total_ = 0;
  bool closed_ = false;

  // Removes the front item (the lock held, the queue not empty); true when it freed room.
  bool TakeFront(std::optional<CameraWork>* out);
};

}  // namespace mvtrack::pipeline
