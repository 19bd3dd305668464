#include "pipeline/executor.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <utility>

#include "core/check.h"

namespace mvtrack::pipeline {
namespace {

// Runs `job` and returns its outcome; never throws.
JobOutcome RunGuarded(const Executor::Job& job, int worker, std::uint64_t seq) {
  JobOutcome outcome;
  outcome.job_seq = seq;
  outcome.worker = worker;
  try {
    job(worker);
  } catch (const std::exception& e) {
    outcome.status = JobStatus::kFailed;
    outcome.error = e.what();
  } catch (...) {
    outcome.status = JobStatus::kFailed;
    outcome.error = "unknown exception";
  }
  return outcome;
}

// Calls `completion` (if any); returns false when it threw. Never throws.
bool CompleteGuarded(const Executor::Completion& completion, const JobOutcome& outcome) {
  if (!completion) return true;
  try {
    completion(outcome);
    return true;
  } catch (...) {
    return false;
  }
}

}  // namespace

// --- Executor ----------------------------------------------------------------------------------

void Executor::ParallelFor(int caller_worker,
                           int n,
                           const std::function<void(int index, int worker)>& fn) {
  for (int i = 0; i < n; ++i) fn(i, caller_worker);
}

// --- InlineExecutor ----------------------------------------------------------------------------

bool InlineExecutor::Submit(Job job, Completion completion) {
  std::uint64_t seq = 0;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (stopped_) return false;
    seq = next_seq_++;
    running_ = true;
  }
  const JobOutcome outcome = RunGuarded(job, 0, seq);
  const bool completion_ok = CompleteGuarded(completion, outcome);
  std::lock_guard<std::mutex> lock(mu_);
  running_ = false;
  ++completed_;
  if (outcome.status == JobStatus::kFailed) ++failed_;
  if (!completion_ok) ++completion_errors_;
  return true;
}

void InlineExecutor::Stop() {
  std::lock_guard<std::mutex> lock(mu_);
  stopped_ = true;
}

ExecutorStats InlineExecutor::stats() const {
  std::lock_guard<std::mutex> lock(mu_);
  ExecutorStats s;
  s.num_workers = 1;
  s.running = running_ ? 1 : 0;
  s.submitted = static_cast<std::int64_t>(next_seq_);
  s.completed = completed_;
  s.failed = failed_;
  s.completion_errors = completion_errors_;
  return s;
}

// --- ThreadPoolExecutor ------------------------------------------------------------------------

bool ThreadPoolOptions::Validate(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (num_workers < 1 || num_workers > 256) return fail("num_workers must be in [1, 256]");
  if (queue_capacity < 1 || queue_capacity > (1 << 20)) {
    return fail("queue_capacity must be in [1, 1048576]");
  }
  return true;
}

ThreadPoolExecutor::ThreadPoolExecutor(ThreadPoolOptions options) : options_(options) {
  std::string why;
  MVTRACK_CHECK_MSG(options_.Validate(&why), why.c_str());
  workers_.reserve(static_cast<std::size_t>(options_.num_workers));
  for (int i = 0; i < options_.num_workers; ++i) {
    workers_.emplace_back([this, i] { WorkerLoop(i); });
  }
}

ThreadPoolExecutor::~ThreadPoolExecutor() { Stop(); }

bool ThreadPoolExecutor::Submit(Job job, Completion completion) {
  {
    std::unique_lock<std::mutex> lock(mu_);
    space_cv_.wait(lock, [&] {
      // ParallelFor helpers do not take up room.
      return stopping_ ||
             queue_.size() - queued_helpers_ < static_cast<std::size_t>(options_.queue_capacity);
    });
    if (stopping_) return false;
    queue_.push_back(Task{next_seq_++, std::move(job), std::move(completion), nullptr});
    ++unfinished_;
  }
  work_cv_.notify_one();
  return true;
}

// The shared state of one ParallelFor: the next unclaimed index and the count of finished calls.
// Helpers hold it by shared_ptr, so one that starts after the ParallelFor returned only finds
// no index left.
struct ThreadPoolExecutor::ForState {
  explicit ForState(int count, const std::function<void(int, int)>* f) : n(count), fn(f) {}
  const int n;
  const std::function<void(int, int)>* const fn;  // valid while an index is unfinished
  std::atomic<int> next{0};
  std::mutex mu;
  std::condition_variable done_cv;
  int done = 0;              // guarded by mu
  std::exception_ptr error;  // first exception of a call, guarded by mu

  // Claims and runs indices until none is left.
  void Work(int worker) {
    while (true) {
      const int i = next.fetch_add(1);
      if (i >= n) return;
      std::exception_ptr thrown;
      try {
        (*fn)(i, worker);
      } catch (...) {
        thrown = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mu);
      if (thrown && !error) error = thrown;
      if (++done == n) done_cv.notify_all();
    }
  }
};

void ThreadPoolExecutor::ParallelFor(int caller_worker,
                                     int n,
                                     const std::function<void(int index, int worker)>& fn) {
  if (n <= 0) return;
  const int helpers = std::min(n - 1, options_.num_workers - 1);
  auto state = std::make_shared<ForState>(n, &fn);
  if (helpers > 0) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      for (int h = 0; h < helpers; ++h) {
        Task task;
        task.helper = state;
        queue_.push_front(std::move(task));
        ++queued_helpers_;
      }
    }
    work_cv_.notify_all();
  }
  state->Work(caller_worker);
  std::unique_lock<std::mutex> lock(state->mu);
  state->done_cv.wait(lock, [&] { return state->done == n; });
  if (state->error) std::rethrow_exception(state->error);
}

void ThreadPoolExecutor::WorkerLoop(int worker) {
  while (true) {
    Task task;
    {
      std::unique_lock<std::mutex> lock(mu_);
      work_cv_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping, and every accepted job has been taken
      task = std::move(queue_.front());
      queue_.pop_front();
      if (task.helper) {
        --queued_helpers_;
      } else {
        ++running_;
      }
    }
    if (task.helper) {
      // A ParallelFor helper: not a job (no outcome, completion or counters).
      task.helper->Work(worker);
      task = Task{};
      continue;
    }
    space_cv_.notify_one();
    const JobOutcome outcome = RunGuarded(task.job, worker, task.seq);
    const bool completion_ok = CompleteGuarded(task.completion, outcome);
    // Destroy the job's captures before reporting it finished (Drain() promises they are gone).
    task = Task{};
    bool idle = false;
    {
      std::lock_guard<std::mutex> lock(mu_);
      --running_;
      --unfinished_;
      ++completed_;
      if (outcome.status == JobStatus::kFailed) ++failed_;
      if (!completion_ok) ++completion_errors_;
      idle = unfinished_ == 0;
    }
    if (idle) idle_cv_.notify_all();
  }
}

void ThreadPoolExecutor::Drain() {
  std::unique_lock<std::mutex> lock(mu_);
  idle_cv_.wait(lock, [&] { return unfinished_ == 0; });
}

void ThreadPoolExecutor::Stop() {
  const std::thread::id self = std::this_thread::get_id();
  std::lock_guard<std::mutex> join_lock(join_mu_);
  for (const std::thread& t : workers_) {
    MVTRACK_CHECK_MSG(t.get_id() != self, "ThreadPoolExecutor::Stop called from a worker");
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    stopping_ = true;
  }
  work_cv_.notify_all();
  space_cv_.notify_all();
  for (std::thread& t : workers_) {
    if (t.joinable()) t.join();
  }
}

ExecutorStats ThreadPoolExecutor::stats() const {
  std::lock_guard<std::mutex> lock(mu_);
  ExecutorStats s;
  s.num_workers = options_.num_workers;
  s.queue_capacity = static_cast<std::size_t>(options_.queue_capacity);
  s.queued = queue_.size() - queued_helpers_;
  s.running = running_;
  s.submitted = static_cast<std::int64_t>(next_seq_);
  s.completed = completed_;
  s.failed = failed_;
  s.completion_errors = completion_errors_;
  return s;
}

}  // namespace mvtrack::pipeline
