#include "pipeline/executor.h"

#include <algorithm>
#include <exception>
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
      return stopping_ || queue_.size() < static_cast<std::size_t>(options_.queue_capacity);
    });
    if (stopping_) return false;
    queue_.push_back(Task{next_seq_++, std::move(job), std::move(completion)});
    ++unfinished_;
  }
  work_cv_.notify_one();
  return true;
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
      ++running_;
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
  s.queued = queue_.size();
  s.running = running_;
  s.submitted = static_cast<std::int64_t>(next_seq_);
  s.completed = completed_;
  s.failed = failed_;
  s.completion_errors = completion_errors_;
  return s;
}

}  // namespace mvtrack::pipeline
