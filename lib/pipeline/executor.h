#pragma once
/// @file
/// Executor: where the pipeline's window jobs run. Two implementations behind one interface
/// (docs/ARCHITECTURE.md; STYLE "Threads live only in lib/pipeline"): InlineExecutor runs each
/// job synchronously inside Submit, in submission order (tests, replay); ThreadPoolExecutor
/// runs jobs on N worker threads fed by a bounded queue (live use). No exception leaves a job:
/// a throwing job becomes a failed JobOutcome.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace mvtrack::pipeline {

/// How a job ended.
enum class JobStatus {
  kOk,      ///< the job returned normally
  kFailed,  ///< the job threw; JobOutcome::error says what
};

/// The outcome of one executed job, handed to its completion.
struct JobOutcome {
  std::uint64_t job_seq = 0;          ///< submission number within the executor, from 0
  int worker = 0;                     ///< index of the worker that ran the job, in [0, num_workers)
  JobStatus status = JobStatus::kOk;  ///< ok or failed
  std::string error;                  ///< kFailed: the exception's what(), or "unknown exception"
};

/// Counters and queue depth of an executor (a consistent snapshot).
struct ExecutorStats {
  int num_workers = 0;                 ///< worker threads (1 for InlineExecutor)
  std::size_t queue_capacity = 0;      ///< bounded queue size (0 for InlineExecutor: no queue)
  std::size_t queued = 0;              ///< jobs waiting for a worker
  int running = 0;                     ///< jobs being run (or their completions)
  std::int64_t submitted = 0;          ///< jobs accepted by Submit
  std::int64_t completed = 0;          ///< jobs finished, ok or failed
  std::int64_t failed = 0;             ///< jobs that threw
  std::int64_t completion_errors = 0;  ///< completions that threw (caught and counted)
};

/// Runs jobs. A job is `void(int worker)`: `worker` is the index in [0, num_workers()) of the
/// thread running it, so a caller can keep one scratch workspace per worker. A worker runs one
/// job at a time. Its completion (optional) runs right after it on the same thread, with the
/// outcome; exceptions from either are caught there and never leave the worker.
class Executor {
 public:
  /// A unit of work; receives the index of the worker running it.
  using Job = std::function<void(int worker)>;
  /// Called once per accepted job, after it ran, on the thread that ran it.
  using Completion = std::function<void(const JobOutcome& outcome)>;

  virtual ~Executor() = default;

  /// Submits a job (and its completion, which may be empty). Returns false, and runs
  /// nothing, once Stop() has been called. See each implementation for blocking behaviour.
  virtual bool Submit(Job job, Completion completion) = 0;
  /// Blocks until every job accepted so far has run and its completion has returned.
  virtual void Drain() = 0;
  /// Refuses new jobs, finishes every accepted job (drain) and releases the workers.
  /// Idempotent. Must not be called from a job or a completion.
  virtual void Stop() = 0;
  /// Number of workers (distinct `worker` indices passed to jobs).
  virtual int num_workers() const = 0;
  /// Fans one job's work out: runs fn(index, worker) for every index in [0, n) and returns when
  /// all calls have returned. Must be called from inside a job, with that job's `caller_worker`;
  /// the caller runs calls itself and idle workers may help. `worker` is the index of the thread
  /// running a call, and a worker runs one job or call at a time, so per-worker scratch space
  /// stays exclusive. Never waits for a busy worker (no deadlock when every worker fans out).
  /// The first exception thrown by a call is rethrown once all calls have returned. This default
  /// runs every call in index order on the caller.
  virtual void ParallelFor(int caller_worker,
                           int n,
                           const std::function<void(int index, int worker)>& fn);
  /// A snapshot of the counters; thread-safe.
  virtual ExecutorStats stats() const = 0;
};

/// Runs every job synchronously inside Submit on the calling thread, with worker index 0, and
/// then its completion: jobs run and complete in submission order. Submit never blocks.
///
/// Thread safety: stats() may be called from any thread; Submit, Drain and Stop from one thread
/// at a time (jobs submitted concurrently would share worker 0). Stop only refuses later jobs
/// (nothing is ever pending).
class InlineExecutor final : public Executor {
 public:
  /// Runs `job` (worker 0), then `completion`, before returning; false once stopped.
  bool Submit(Job job, Completion completion) override;
  /// Nothing to wait for: every job completed inside its Submit.
  void Drain() override {}
  /// Refuses later jobs.
  void Stop() override;
  /// Always 1 (worker index 0).
  int num_workers() const override { return 1; }
  /// Counters (queue_capacity and queued are 0: there is no queue).
  ExecutorStats stats() const override;

 private:
  mutable std::mutex mu_;  // guards the fields below (never held while a job runs)
  bool stopped_ = false;
  bool running_ = false;
  std::uint64_t next_seq_ = 0;
  std::int64_t completed_ = 0;
  std::int64_t failed_ = 0;
  std::int64_t completion_errors_ = 0;
};

/// Options of ThreadPoolExecutor.
struct ThreadPoolOptions {
  /// Worker threads, in [1, 256].
  int num_workers = 2;
  /// Jobs waiting for a worker, in [1, 1 << 20]. When the queue is full, Submit blocks until a
  /// worker takes a job (back-pressure on the submitter; nothing is dropped).
  int queue_capacity = 64;

  /// Checks the ranges above; on failure writes a reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// N worker threads fed by a bounded FIFO queue (in the spirit of colmap's JobQueue and ceres'
/// ConcurrentQueue). Jobs start in submission order; they may finish in any order.
///
/// Full queue policy: Submit blocks the submitter until there is room (back-pressure).
/// Stop/drain protocol: Stop() refuses new jobs (a Submit blocked on a full queue returns
/// false), lets the workers run every job already accepted, then joins them. The destructor
/// calls Stop(). Exceptions from jobs become failed outcomes; exceptions from completions are
/// caught and counted.
///
/// Thread safety: every method is thread-safe. Jobs and completions must not call Stop() (it
/// would join its own thread; checked), nor Submit() when the queue can be full (deadlock).
class ThreadPoolExecutor final : public Executor {
 public:
  /// `options` must be valid (checked). Starts the workers.
  explicit ThreadPoolExecutor(ThreadPoolOptions options);
  /// Stop()s (drains, then joins the workers).
  ~ThreadPoolExecutor() override;
  ThreadPoolExecutor(const ThreadPoolExecutor&) = delete;
  ThreadPoolExecutor& operator=(const ThreadPoolExecutor&) = delete;

  /// Blocks while the queue is full; false once stopping.
  bool Submit(Job job, Completion completion) override;
  /// Waits until the queue is empty and no job or completion is running.
  void Drain() override;
  /// See the class comment (stop/drain protocol).
  void Stop() override;
  /// ThreadPoolOptions::num_workers.
  int num_workers() const override { return options_.num_workers; }
  /// Queues up to num_workers - 1 helper tasks ahead of every waiting job (beyond the queue's
  /// capacity; they are not counted as jobs) and takes part itself: each taker claims the next
  /// index until none is left; a helper that starts after that returns at once.
  void ParallelFor(int caller_worker,
                   int n,
                   const std::function<void(int index, int worker)>& fn) override;
  /// A consistent snapshot (taken under the queue's lock).
  ExecutorStats stats() const override;

 private:
  struct ForState;
  struct Task {
    std::uint64_t seq = 0;
    Job job;
    Completion completion;
    std::shared_ptr<ForState> helper;  // set: a ParallelFor helper, not a job
  };

  void WorkerLoop(int worker);

  const ThreadPoolOptions options_;
  mutable std::mutex mu_;
  std::condition_variable work_cv_;   // a task is queued, or stopping
  std::condition_variable space_cv_;  // the queue has room, or stopping
  std::condition_variable idle_cv_;   // every accepted task has finished
  std::deque<Task> queue_;
  std::size_t queued_helpers_ = 0;  // ParallelFor helpers in queue_
  bool stopping_ = false;
  int running_ = 0;
  std::int64_t unfinished_ = 0;  // accepted, completion not yet returned
  std::uint64_t next_seq_ = 0;
  std::int64_t completed_ = 0;
  std::int64_t failed_ = 0;
  std::int64_t completion_errors_ = 0;

  std::mutex join_mu_;  // serialises Stop()'s joining
  std::vector<std::thread> workers_;
};

}  // namespace mvtrack::pipeline
