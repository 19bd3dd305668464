// CameraQueue (overflow policies), BoundedQueue, SequenceReorderBuffer and the clocks.

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <thread>
#include <vector>

#include "pipeline/bounded_queue.h"
#include "pipeline/camera_queue.h"
#include "pipeline/clock.h"
#include "pipeline/reorder_buffer.h"

namespace mvtrack::pipeline {
namespace {

CameraWork Work(std::uint64_t seq, std::size_t detections = 3) {
  CameraWork w;
  w.seq = seq;
  w.frame.frame = static_cast<FrameIndex>(100 + seq);
  w.frame.utime = static_cast<Utime>(1000 * seq);
  w.frame.detections.resize(detections);
  return w;
}

TEST_CASE("CameraQueue drop-oldest: the oldest waiting camera-frames lose their detections",
          "[unit][pipeline]") {
  CameraQueue queue(3, OverflowPolicy::kDropOldest);
  for (std::uint64_t s = 0; s < 5; ++s) REQUIRE(queue.Push(Work(s)));  // never blocks
  CHECK(queue.dropped() == 2);
  CHECK(queue.depth() == 3);  // at most the capacity: the 2 dropped headers are not counted
  for (std::uint64_t s = 0; s < 5; ++s) {
    const std::optional<CameraWork> w = queue.Pop();
    REQUIRE(w);
    CHECK(w->seq == s);  // order kept
    CHECK(w->frame.frame == static_cast<FrameIndex>(100 + s));
    CHECK(w->frame.utime == static_cast<Utime>(1000 * s));
    const bool oldest = s < 2;
    CHECK(w->dropped == oldest);
    CHECK(w->frame.detections.size() == (oldest ? 0u : 3u));
  }
  // Popped items free room: three more fit without a drop, the fourth drops the oldest (seq 5).
  for (std::uint64_t s = 5; s < 9; ++s) REQUIRE(queue.Push(Work(s)));
  CHECK(queue.dropped() == 3);
  std::vector<std::uint64_t> dropped_seqs;
  for (int i = 0; i < 4; ++i) {
    const auto w = queue.Pop();
    if (w->dropped) dropped_seqs.push_back(w->seq);
  }
  CHECK(dropped_seqs == std::vector<std::uint64_t>{5});
}

TEST_CASE("CameraQueue block: a full queue makes Push wait for the consumer",
          "[unit][threads][pipeline]") {
  CameraQueue queue(2, OverflowPolicy::kBlock);
  REQUIRE(queue.Push(Work(0)));
  REQUIRE(queue.Push(Work(1)));
  std::atomic<bool> entered{false};
  std::atomic<bool> returned{false};
  std::thread producer([&] {
    entered = true;
    returned = queue.Push(Work(2));
  });
  while (!entered) std::this_thread::yield();
  for (int i = 0; i < 1000; ++i) std::this_thread::yield();
  CHECK_FALSE(returned.load());
  CHECK(queue.depth() == 2);
  const auto first = queue.Pop();
  producer.join();
  CHECK(returned);
  CHECK(first->seq == 0);
  CHECK(queue.dropped() == 0);
  CHECK(queue.Pop()->seq == 1);
  CHECK(queue.Pop()->seq == 2);
}

TEST_CASE("CameraQueue close: Pop drains, then ends, Push is refused", "[unit][pipeline]") {
  CameraQueue queue(4, OverflowPolicy::kDropOldest);
  REQUIRE(queue.Push(Work(0)));
  REQUIRE(queue.Push(Work(1)));
  queue.Close();
  CHECK_FALSE(queue.Push(Work(2)));
  CHECK(queue.Pop()->seq == 0);
  CHECK(queue.Pop()->seq == 1);
  CHECK_FALSE(queue.Pop().has_value());
}

TEST_CASE("BoundedQueue: FIFO, back-pressure, close", "[unit][threads][pipeline]") {
  BoundedQueue<int> queue(2);
  REQUIRE(queue.Push(1));
  REQUIRE(queue.Push(2));
  std::atomic<bool> returned{false};
  std::thread producer([&] { returned = queue.Push(3); });
  for (int i = 0; i < 1000; ++i) std::this_thread::yield();
  CHECK_FALSE(returned.load());
  CHECK(queue.size() == 2);
  CHECK(queue.Pop() == 1);
  producer.join();
  CHECK(returned);
  CHECK(queue.Pop() == 2);
  CHECK(queue.Pop() == 3);
  queue.Close();
  CHECK_FALSE(queue.Push(4));
  CHECK_FALSE(queue.Pop().has_value());
}

TEST_CASE("SequenceReorderBuffer delivers in sequence order whatever the producers' timing",
          "[unit][threads][pipeline]") {
  constexpr int kProducers = 4;
  constexpr std::uint64_t kItems = 4000;
  constexpr std::size_t kCapacity = 16;
  SequenceReorderBuffer<std::uint64_t> buffer(kCapacity);
  std::vector<std::thread> producers;
  for (int p = 0; p < kProducers; ++p) {
    // Producer p owns the numbers congruent to p, each in increasing order (as a camera thread).
    producers.emplace_back([&buffer, p] {
      for (std::uint64_t s = static_cast<std::uint64_t>(p); s < kItems; s += kProducers) {
        buffer.Insert(s, s * 3);
        if (s % 7 == 0) std::this_thread::yield();
      }
    });
  }
  std::size_t max_buffered = 0;
  bool in_order = true;
  for (std::uint64_t s = 0; s < kItems; ++s) {
    max_buffered = std::max(max_buffered, buffer.size());
    in_order = in_order && buffer.PopNext() == s * 3;
  }
  for (std::thread& t : producers) t.join();
  CHECK(in_order);
  CHECK(max_buffered <= kCapacity);
  CHECK(buffer.size() == 0);
  CHECK(buffer.next() == kItems);
  // A control item may be inserted beyond the look-ahead without waiting.
  buffer.Insert(kItems + 100, 7, /*wait_for_room=*/false);
  CHECK(buffer.size() == 1);
}

TEST_CASE("SequenceReorderBuffer wakes each waiting producer when its number is admitted",
          "[unit][threads][pipeline]") {
  // 32 producers (a camera thread each) against a look-ahead of 1: nearly every insert waits,
  // and only the pop that admits a number wakes its producer. A missed wake-up would hang here.
  constexpr int kProducers = 32;
  constexpr std::uint64_t kItems = 32 * 200;
  SequenceReorderBuffer<std::uint64_t> buffer(1);
  std::vector<std::thread> producers;
  for (int p = 0; p < kProducers; ++p) {
    producers.emplace_back([&buffer, p] {
      for (std::uint64_t s = static_cast<std::uint64_t>(p); s < kItems; s += kProducers) {
        buffer.Insert(s, s + 1);
      }
    });
  }
  bool in_order = true;
  for (std::uint64_t s = 0; s < kItems; ++s) in_order = in_order && buffer.PopNext() == s + 1;
  for (std::thread& t : producers) t.join();
  CHECK(in_order);
  CHECK(buffer.size() == 0);
}

TEST_CASE("ManualClock moves only when told, SteadyClock never goes back", "[unit][pipeline]") {
  ManualClock manual(5);
  CHECK(manual.NowMicros() == 5);
  manual.AdvanceMicros(10);
  CHECK(manual.NowMicros() == 15);
  manual.SetMicros(1700000000000000);
  CHECK(manual.NowMicros() == 1700000000000000);
  SteadyClock steady;
  std::int64_t previous = steady.NowMicros();
  for (int i = 0; i < 1000; ++i) {
    const std::int64_t now = steady.NowMicros();
    CHECK(now >= previous);
    previous = now;
  }
}

}  // namespace
}  // namespace mvtrack::pipeline
