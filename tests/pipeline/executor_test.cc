// Executors: ordering, drain, stop, exceptions -> failed outcomes, bounded queue back-pressure.

#include "pipeline/executor.h"

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <latch>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

namespace mvtrack::pipeline {
namespace {

TEST_CASE("InlineExecutor runs each job inside Submit, in submission order", "[unit][pipeline]") {
  InlineExecutor executor;
  std::vector<int> ran;
  std::vector<JobOutcome> outcomes;
  for (int i = 0; i < 5; ++i) {
    REQUIRE(executor.Submit(
        [&ran, i](int worker) {
          CHECK(worker == 0);
          ran.push_back(i);
        },
        [&outcomes](const JobOutcome& o) { outcomes.push_back(o); }));
    // Synchronous: the job and its completion ran before Submit returned.
    CHECK(ran.size() == static_cast<std::size_t>(i + 1));
    CHECK(outcomes.size() == static_cast<std::size_t>(i + 1));
  }
  CHECK(ran == std::vector<int>{0, 1, 2, 3, 4});
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    CHECK(outcomes[i].job_seq == i);
    CHECK(outcomes[i].status == JobStatus::kOk);
  }
  const ExecutorStats s = executor.stats();
  CHECK(s.submitted == 5);
  CHECK(s.completed == 5);
  CHECK(s.num_workers == 1);
  executor.Stop();
  CHECK_FALSE(executor.Submit([&ran](int) { ran.push_back(99); }, {}));
  CHECK(ran.size() == 5);
}

// Runs a throwing job, a job throwing a non-std exception and a throwing completion on
// `executor`, then a normal job: every failure is reported, nothing escapes, work continues.
void CheckExceptionsBecomeFailures(Executor* executor) {
  std::mutex mu;
  std::vector<JobOutcome> outcomes;
  auto record = [&](const JobOutcome& o) {
    std::lock_guard<std::mutex> lock(mu);
    outcomes.push_back(o);
  };
  REQUIRE(executor->Submit([](int) { throw std::runtime_error("bad window"); }, record));
  REQUIRE(executor->Submit([](int) { throw 42; }, record));
  REQUIRE(executor->Submit([](int) {}, [](const JobOutcome&) { throw std::logic_error("cb"); }));
  std::atomic<bool> later_ran{false};
  REQUIRE(executor->Submit([&](int) { later_ran = true; }, record));
  executor->Drain();
  CHECK(later_ran);
  std::lock_guard<std::mutex> lock(mu);
  REQUIRE(outcomes.size() == 3);
  std::sort(outcomes.begin(), outcomes.end(), [](const JobOutcome& a, const JobOutcome& b) {
    return a.job_seq < b.job_seq;
  });
  CHECK(outcomes[0].status == JobStatus::kFailed);
  CHECK(outcomes[0].error == "bad window");
  CHECK(outcomes[1].status == JobStatus::kFailed);
  CHECK(outcomes[1].error == "unknown exception");
  CHECK(outcomes[2].status == JobStatus::kOk);
  CHECK(outcomes[2].job_seq == 3);
  const ExecutorStats s = executor->stats();
  CHECK(s.submitted == 4);
  CHECK(s.completed == 4);
  CHECK(s.failed == 2);
  CHECK(s.completion_errors == 1);
}

TEST_CASE("a throwing job becomes a failed outcome (inline)", "[unit][pipeline]") {
  InlineExecutor executor;
  CheckExceptionsBecomeFailures(&executor);
}

TEST_CASE("a throwing job becomes a failed outcome, the worker survives (pool)",
          "[unit][threads][pipeline]") {
  ThreadPoolExecutor executor({/*num_workers=*/2, /*queue_capacity=*/4});
  CheckExceptionsBecomeFailures(&executor);
}

TEST_CASE("ThreadPoolExecutor runs every job once, one worker keeps submission order",
          "[unit][threads][pipeline]") {
  for (int workers : {1, 3}) {
    INFO(workers << " workers");
    ThreadPoolExecutor executor({workers, 8});
    constexpr int kJobs = 200;
    std::vector<std::atomic<int>> runs(kJobs);
    std::mutex mu;
    std::vector<int> order;
    std::atomic<bool> worker_in_range{true};
    for (int i = 0; i < kJobs; ++i) {
      REQUIRE(executor.Submit(
          [&, i](int worker) {
            if (worker < 0 || worker >= workers) worker_in_range = false;
            runs[static_cast<std::size_t>(i)].fetch_add(1);
            std::lock_guard<std::mutex> lock(mu);
            order.push_back(i);
          },
          {}));
    }
    executor.Drain();
    CHECK(worker_in_range);
    for (const auto& r : runs) CHECK(r.load() == 1);
    const ExecutorStats s = executor.stats();
    CHECK(s.completed == kJobs);
    CHECK(s.queued == 0);
    CHECK(s.running == 0);
    if (workers == 1) {
      std::vector<int> expected(kJobs);
      for (int i = 0; i < kJobs; ++i) expected[static_cast<std::size_t>(i)] = i;
      CHECK(order == expected);
    }
  }
}

TEST_CASE("ThreadPoolExecutor: a full queue blocks the submitter until a worker takes a job",
          "[unit][threads][pipeline]") {
  constexpr int kCapacity = 2;
  ThreadPoolExecutor executor({/*num_workers=*/1, kCapacity});
  std::latch gate(1);
  std::atomic<bool> first_done{false};
  REQUIRE(executor.Submit(
      [&](int) {
        gate.wait();  // the only worker is stuck here until the test opens the gate
        first_done = true;
      },
      {}));
  // Wait until the worker has taken the first job, then fill the queue.
  while (executor.stats().running == 0) std::this_thread::yield();
  for (int i = 0; i < kCapacity; ++i) REQUIRE(executor.Submit([](int) {}, {}));
  CHECK(executor.stats().queued == kCapacity);

  std::atomic<bool> entered{false};
  std::atomic<bool> returned{false};
  std::atomic<bool> first_done_when_returned{false};
  std::thread submitter([&] {
    entered = true;
    const bool ok = executor.Submit([](int) {}, {});
    first_done_when_returned = first_done.load();
    returned = ok;
  });
  while (!entered) std::this_thread::yield();
  for (int i = 0; i < 1000; ++i) {
    // The queue never holds more than its capacity while the worker is stuck.
    CHECK(executor.stats().queued <= kCapacity);
    std::this_thread::yield();
  }
  CHECK_FALSE(returned.load());
  gate.count_down();
  submitter.join();
  CHECK(returned);
  // Room appeared only when the worker finished the first job and took the next one.
  CHECK(first_done_when_returned);
  executor.Drain();
  CHECK(executor.stats().completed == 4);
}

TEST_CASE("ThreadPoolExecutor: Stop runs every accepted job, then refuses new ones",
          "[unit][threads][pipeline]") {
  ThreadPoolExecutor executor({/*num_workers=*/2, /*queue_capacity=*/64});
  std::latch gate(1);
  std::atomic<int> ran{0};
  std::atomic<int> completed{0};
  for (int i = 0; i < 40; ++i) {
    REQUIRE(executor.Submit(
        [&](int) {
          gate.wait();
          ++ran;
        },
        [&](const JobOutcome&) { ++completed; }));
  }
  std::thread stopper([&] { executor.Stop(); });
  gate.count_down();
  stopper.join();
  CHECK(ran == 40);
  CHECK(completed == 40);
  CHECK_FALSE(executor.Submit([&](int) { ++ran; }, {}));
  executor.Stop();  // idempotent
  CHECK(ran == 40);
  CHECK(executor.stats().completed == 40);
}

TEST_CASE("ThreadPoolExecutor: Drain waits for every completion", "[unit][threads][pipeline]") {
  ThreadPoolExecutor executor({/*num_workers=*/4, /*queue_capacity=*/16});
  std::atomic<int> completions{0};
  for (int round = 0; round < 3; ++round) {
    for (int i = 0; i < 50; ++i) {
      REQUIRE(executor.Submit([](int) {}, [&](const JobOutcome&) { ++completions; }));
    }
    executor.Drain();
    CHECK(completions == 50 * (round + 1));
  }
}

TEST_CASE("ThreadPoolOptions are validated", "[unit][pipeline]") {
  std::string why;
  CHECK(ThreadPoolOptions{}.Validate(&why));
  CHECK_FALSE(ThreadPoolOptions{0, 4}.Validate(&why));
  CHECK_THAT(why, Catch::Contains("num_workers"));
  CHECK_FALSE(ThreadPoolOptions{2, 0}.Validate(&why));
  CHECK_THAT(why, Catch::Contains("queue_capacity"));
}

TEST_CASE("ParallelFor runs every index once, each worker on one call at a time",
          "[unit][threads][pipeline]") {
  ThreadPoolOptions options;
  options.num_workers = 3;
  ThreadPoolExecutor executor(options);
  constexpr int kJobs = 6;
  constexpr int kIndices = 200;
  std::vector<std::atomic<int>> runs(kJobs * kIndices);
  std::vector<std::atomic<int>> busy(3);
  std::atomic<int> overlaps{0};
  std::atomic<int> bad_worker{0};
  for (int job = 0; job < kJobs; ++job) {
    REQUIRE(executor.Submit(
        [&, job](int caller) {
          // Every job fans out, so workers are often busy with their own job's calls.
          executor.ParallelFor(caller, kIndices, [&, job](int index, int worker) {
            if (worker < 0 || worker >= 3) {
              ++bad_worker;
              return;
            }
            if (busy[static_cast<std::size_t>(worker)].fetch_add(1) != 0) ++overlaps;
            ++runs[static_cast<std::size_t>(job * kIndices + index)];
            std::this_thread::sleep_for(std::chrono::microseconds(50));
            busy[static_cast<std::size_t>(worker)].fetch_sub(1);
          });
        },
        {}));
  }
  executor.Drain();
  CHECK(bad_worker == 0);
  CHECK(overlaps == 0);
  for (const std::atomic<int>& r : runs) REQUIRE(r == 1);
  const ExecutorStats stats = executor.stats();
  CHECK(stats.submitted == kJobs);
  CHECK(stats.completed == kJobs);
  CHECK(stats.failed == 0);
}

TEST_CASE("ParallelFor: an idle worker takes part", "[unit][threads][pipeline]") {
  ThreadPoolOptions options;
  options.num_workers = 2;
  ThreadPoolExecutor executor(options);
  std::atomic<int> index0_worker{-1};
  std::atomic<int> index1_worker{-1};
  std::atomic<bool> index1_started{false};
  REQUIRE(executor.Submit(
      [&](int caller) {
        executor.ParallelFor(caller, 2, [&](int index, int worker) {
          if (index == 1) {
            index1_worker = worker;
            index1_started = true;
            return;
          }
          // Index 0 holds its taker until index 1 has started: only another worker can take it.
          index0_worker = worker;
          const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
          while (!index1_started && std::chrono::steady_clock::now() < give_up) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
          }
        });
      },
      {}));
  executor.Drain();
  REQUIRE(index1_started);
  CHECK(index0_worker != index1_worker);
}

TEST_CASE("ParallelFor rethrows a call's exception after every call returned",
          "[unit][threads][pipeline]") {
  ThreadPoolOptions options;
  options.num_workers = 2;
  ThreadPoolExecutor executor(options);
  std::atomic<int> calls{0};
  std::vector<JobOutcome> outcomes;
  std::mutex mu;
  REQUIRE(executor.Submit(
      [&](int caller) {
        executor.ParallelFor(caller, 50, [&](int index, int) {
          ++calls;
          if (index == 7) throw std::runtime_error("index 7 failed");
        });
      },
      [&](const JobOutcome& o) {
        std::lock_guard<std::mutex> lock(mu);
        outcomes.push_back(o);
      }));
  executor.Drain();
  CHECK(calls == 50);
  REQUIRE(outcomes.size() == 1);
  CHECK(outcomes[0].status == JobStatus::kFailed);
  CHECK(outcomes[0].error == "index 7 failed");
}

TEST_CASE("InlineExecutor ParallelFor runs the calls in order on worker 0", "[unit][pipeline]") {
  InlineExecutor executor;
  std::vector<int> order;
  REQUIRE(executor.Submit(
      [&](int caller) {
        executor.ParallelFor(caller, 5, [&](int index, int worker) {
          CHECK(worker == 0);
          order.push_back(index);
        });
      },
      {}));
  CHECK(order == std::vector<int>{0, 1, 2, 3, 4});
}

}  // namespace
}  // namespace mvtrack::pipeline
