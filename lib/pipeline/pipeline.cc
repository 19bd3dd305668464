#include "pipeline/pipeline.h"

#include <algorithm>
#include <exception>
#include <utility>
#include <variant>

#include "core/check.h"

namespace mvtrack::pipeline {

bool PipelineOptions::Validate(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (camera_queue_capacity < 1) return fail("camera_queue_capacity must be >= 1");
  if (camera_overflow != OverflowPolicy::kDropOldest && camera_overflow != OverflowPolicy::kBlock) {
    return fail("camera_overflow must be drop_oldest or block");
  }
  if (reorder_capacity < 1) return fail("reorder_capacity must be >= 1");
  if (finalizer_queue_capacity < 1) return fail("finalizer_queue_capacity must be >= 1");
  if (camera_threads < 0) return fail("camera_threads must be >= 0");
  return true;
}

std::unique_ptr<Pipeline> Pipeline::Create(geometry::CameraRig rig,
                                           tracker::TrackerOptions options,
                                           PipelineOptions pipeline_options,
                                           std::unique_ptr<Executor> executor,
                                           const Clock& clock,
                                           FrameCallback on_frame,
                                           std::string* why,
                                           FrameCallback on_provisional) {
  auto fail = [&](std::string reason) -> std::unique_ptr<Pipeline> {
    if (why != nullptr) *why = std::move(reason);
    return nullptr;
  };
  if (!options.Validate(why)) return nullptr;
  std::string reason;
  if (!pipeline_options.Validate(&reason)) return fail("pipeline: " + reason);
  if (rig.size() < 2) {
    return fail("the camera rig has " + std::to_string(rig.size()) +
                " camera(s); at least 2 are needed to triangulate");
  }
  if (executor == nullptr) return fail("the pipeline needs an executor");
  if (!on_frame) return fail("the pipeline needs an output callback");
  std::unique_ptr<Pipeline> p(new Pipeline(std::move(rig),
                                           std::move(options),
                                           pipeline_options,
                                           std::move(executor),
                                           clock,
                                           std::move(on_frame),
                                           std::move(on_provisional)));
  p->Start();
  return p;
}

Pipeline::Pipeline(geometry::CameraRig rig,
                   tracker::TrackerOptions options,
                   PipelineOptions pipeline_options,
                   std::unique_ptr<Executor> executor,
                   const Clock& clock,
                   FrameCallback on_frame,
                   FrameCallback on_provisional)
    : rig_(tracker::WithSharedViews(std::move(rig), options)),
      options_(std::move(options)),
      pipeline_options_(pipeline_options),
      clock_(clock),
      on_frame_(std::move(on_frame)),
      on_provisional_(std::move(on_provisional)),
      executor_(std::move(executor)),
      gate_(rig_, options_),
      reorder_(static_cast<std::size_t>(pipeline_options_.reorder_capacity)),
      builder_(rig_, options_, /*keep_frame_views=*/static_cast<bool>(on_provisional_)),
      steps_(static_cast<std::size_t>(pipeline_options_.finalizer_queue_capacity)),
      finalizer_(rig_, options_) {
  int threads = pipeline_options_.camera_threads;
  if (threads == 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::clamp(threads, 1, std::max(1, rig_.size()));
  for (int k = 0; k < threads; ++k) camera_signals_.push_back(std::make_unique<WorkSignal>());
  for (int c = 0; c < rig_.size(); ++c) {
    camera_queues_.push_back(std::make_unique<CameraQueue>(
        pipeline_options_.camera_queue_capacity,
        pipeline_options_.camera_overflow,
        camera_signals_[static_cast<std::size_t>(c % threads)].get()));
    stages_.push_back(std::make_unique<tracker::CameraStage>(rig_.camera(c), c, options_));
  }
  if (on_provisional_) provisional_.emplace(rig_, options_);
  camera_counters_.resize(static_cast<std::size_t>(rig_.size()));
  gallery_memory_ = tracker::GalleryMemory(static_cast<std::size_t>(rig_.size()));
  const int workers = executor_->num_workers();
  MVTRACK_CHECK(workers >= 1);
  workspaces_.reserve(static_cast<std::size_t>(workers));
  for (int w = 0; w < workers; ++w) workspaces_.emplace_back(options_.triangulation);
}

void Pipeline::Start() {
  finalizer_thread_ = std::thread([this] { FinalizerLoop(); });
  finalizer_thread_id_ = finalizer_thread_.get_id();
  scheduler_thread_ = std::thread([this] { SchedulerLoop(); });
  for (int k = 0; k < static_cast<int>(camera_signals_.size()); ++k) {
    camera_threads_.emplace_back([this, k] { CameraWorkerLoop(k); });
  }
}

Pipeline::~Pipeline() { Stop(); }

SubmitResult Pipeline::Submit(core::CameraFrame frame) {
  SubmitResult result;
  std::lock_guard<std::mutex> input_lock(input_mu_);
  if (stopping_) {
    result.status = SubmitStatus::kStopped;
    return result;
  }
  const tracker::FrameAdmission admission = gate_.Admit(frame);
  if (admission.rejection != tracker::FrameRejection::kNone) {
    {
      std::lock_guard<std::mutex> lock(status_mu_);
      ++stats_.camera_frames_rejected;
      ++stats_.rejections[admission.rejection];
    }
    result.status = SubmitStatus::kRejected;
    result.rejection = admission.rejection;
    result.reason = admission.reason;
    return result;
  }
  {
    std::lock_guard<std::mutex> lock(status_mu_);
    ++stats_.camera_frames_accepted;
    if (admission.events.reanchor) ++stats_.reanchors;
  }
  result.seq = next_seq_++;
  CameraWork work;
  work.seq = result.seq;
  work.events = admission.events;
  work.stream_epoch = admission.stream_epoch;
  work.frame = std::move(frame);
  // Queues are closed only by Stop(), after stopping_ was set under input_mu_.
  const bool queued =
      camera_queues_[static_cast<std::size_t>(admission.camera_index)]->Push(std::move(work));
  MVTRACK_CHECK(queued);
  return result;
}

bool Pipeline::Flush() {
  MVTRACK_CHECK_MSG(std::this_thread::get_id() != finalizer_thread_id_,
                    "Pipeline::Flush called from the output callback");
  std::uint64_t ticket = 0;
  {
    std::lock_guard<std::mutex> input_lock(input_mu_);
    if (stopping_) return false;
    gate_.Flush();
    ticket = ++flush_requested_;
    SequencedItem item;
    item.kind = SequencedItem::Kind::kFlush;
    item.flush_ticket = ticket;
    reorder_.Insert(next_seq_++, std::move(item), /*wait_for_room=*/false);
  }
  std::unique_lock<std::mutex> lock(flush_mu_);
  flush_cv_.wait(lock, [&] { return flush_done_ >= ticket; });
  return true;
}

void Pipeline::Stop() {
  MVTRACK_CHECK_MSG(std::this_thread::get_id() != finalizer_thread_id_,
                    "Pipeline::Stop called from the output callback");
  std::lock_guard<std::mutex> stop_lock(stop_mu_);
  if (stopped_) return;
  {
    std::lock_guard<std::mutex> input_lock(input_mu_);
    stopping_ = true;
    gate_.Flush();
    SequencedItem item;
    item.kind = SequencedItem::Kind::kStop;
    reorder_.Insert(next_seq_++, std::move(item), /*wait_for_room=*/false);
  }
  // Camera threads finish what is queued, then the scheduler reaches the stop item (it flushes
  // the WindowBuilder, as Tracker::Flush), then the finalizer links every window and outputs
  // every frame.
  for (auto& queue : camera_queues_) queue->Close();
  for (std::thread& t : camera_threads_) t.join();
  scheduler_thread_.join();
  finalizer_thread_.join();
  executor_->Drain();
  executor_->Stop();
  stopped_ = true;
}

void Pipeline::CameraWorkerLoop(int worker) {
  const auto n = static_cast<int>(camera_signals_.size());
  std::vector<int> mine;
  for (int c = worker; c < rig_.size(); c += n) mine.push_back(c);
  WorkSignal& signal = *camera_signals_[static_cast<std::size_t>(worker)];
  while (true) {
    // The oldest waiting item of this thread's cameras: its reorder-buffer insert may wait for
    // room, which only items with lower sequence numbers make, and every one of those is ahead
    // of it on its own thread (sequence numbers are handed out in push order), so no thread
    // waits for one behind it.
    int best = -1;
    std::uint64_t best_seq = 0;
    bool finished = true;
    for (const int c : mine) {
      const CameraQueue& queue = *camera_queues_[static_cast<std::size_t>(c)];
      if (const std::optional<std::uint64_t> seq = queue.FrontSeq()) {
        finished = false;
        if (best < 0 || *seq < best_seq) {
          best = c;
          best_seq = *seq;
        }
      } else if (!queue.Finished()) {
        finished = false;
      }
    }
    if (best < 0) {
      if (finished) return;
      signal.Wait();  // a push or a close since the look above returns at once
      continue;
    }
    std::optional<CameraWork> work = camera_queues_[static_cast<std::size_t>(best)]->TryPop();
    MVTRACK_CHECK(work.has_value());  // only this thread takes from its cameras' queues
    ProcessCameraWork(best, std::move(*work));
  }
}

void Pipeline::ProcessCameraWork(int camera_index, CameraWork work) {
  const auto c = static_cast<std::size_t>(camera_index);
  tracker::CameraStage& stage = *stages_[c];
  SequencedItem item;
  item.kind = SequencedItem::Kind::kCameraFrame;
  item.events = work.events;
  if (work.dropped) {
    // Overflow: the frame still takes part in frame sequencing, without detections; SORT
    // does not see it (a skipped frame for this camera).
    item.frame.camera_index = camera_index;
    item.frame.frame = work.frame.frame;
    item.frame.utime = work.frame.utime;
  } else {
    tracker::CameraStageCounters counters;
    item.frame = stage.Process(work.frame, work.stream_epoch, &counters);
    std::lock_guard<std::mutex> lock(status_mu_);
    ++camera_counters_[c].frames_processed;
    camera_counters_[c].detections_rejected += counters.detections_rejected;
    camera_counters_[c].embeddings_dropped += counters.embeddings_dropped;
    gallery_memory_.SetCamera(c, counters.sort_gallery_bytes);
    stats_.gallery_bytes = gallery_memory_.total();
    stats_.detections_used += counters.detections_used;
    stats_.detections_rejected += counters.detections_rejected;
    stats_.detections_repaired += counters.detections_repaired;
    stats_.detections_filtered += counters.detections_filtered;
    stats_.embeddings_used += counters.embeddings_used;
    stats_.embeddings_dropped += counters.embeddings_dropped;
  }
  reorder_.Insert(work.seq, std::move(item));
}

void Pipeline::SchedulerLoop() {
  std::vector<tracker::BuilderOutput> outputs;
  while (true) {
    SequencedItem item = reorder_.PopNext();
    outputs.clear();
    if (item.kind == SequencedItem::Kind::kCameraFrame) {
      builder_.Add(item.events, std::move(item.frame), &outputs);
    } else {
      builder_.Flush(&outputs);
    }
    for (tracker::BuilderOutput& output : outputs) DispatchOutput(&output);
    if (item.kind == SequencedItem::Kind::kFlush) {
      Step step;
      step.kind = Step::Kind::kFlushDone;
      step.flush_ticket = item.flush_ticket;
      steps_.Push(std::move(step));
    } else if (item.kind == SequencedItem::Kind::kStop) {
      Step step;
      step.kind = Step::Kind::kStop;
      steps_.Push(std::move(step));
      return;
    }
  }
}

void Pipeline::DispatchOutput(tracker::BuilderOutput* output) {
  Step step;
  if (tracker::ClosedFrame* closed = std::get_if<tracker::ClosedFrame>(output)) {
    step.kind = Step::Kind::kClosedFrame;
    step.closed = std::move(*closed);
    steps_.Push(std::move(step));
    return;
  }
  if (std::holds_alternative<tracker::StreamEnd>(*output)) {
    step.kind = Step::Kind::kStreamEnd;
    steps_.Push(std::move(step));
    return;
  }
  auto job =
      std::make_shared<const tracker::WindowJob>(std::move(std::get<tracker::WindowJob>(*output)));
  step.kind = Step::Kind::kWindow;
  step.window_id = job->window_id;
  step.close_time_us = clock_.NowMicros();
  steps_.Push(std::move(step));
  {
    std::lock_guard<std::mutex> lock(status_mu_);
    ++windows_submitted_;
  }
  // The job reads only immutable data (rig_, options_, *job) and its worker's workspace; the
  // completion runs on the same worker right after it, so `slot` needs no lock.
  auto slot = std::make_shared<tracker::WindowResult>();
  const bool submitted = executor_->Submit(
      [this, job, slot](int worker) {
        MVTRACK_CHECK(worker >= 0 && static_cast<std::size_t>(worker) < workspaces_.size());
        // The window's persons are spread over idle workers (each on its own workspace); the
        // result is the same as on one thread.
        const tracker::PersonLoop person_loop = [this, worker](int n,
                                                               const tracker::PersonTask& task) {
          executor_->ParallelFor(worker, n, [&](int i, int w) {
            MVTRACK_CHECK(w >= 0 && static_cast<std::size_t>(w) < workspaces_.size());
            task(i, &workspaces_[static_cast<std::size_t>(w)]);
          });
        };
        *slot = tracker::ProcessWindowJob(
            rig_, options_, *job, &workspaces_[static_cast<std::size_t>(worker)], person_loop);
      },
      [this, job, slot](const JobOutcome& outcome) {
        FinishWindow(*job, std::move(*slot), outcome);
      });
  MVTRACK_CHECK_MSG(submitted, "the pipeline's executor was stopped while running");
}

void Pipeline::FinishWindow(const tracker::WindowJob& job,
                            tracker::WindowResult result,
                            const JobOutcome& outcome) {
  FinishedWindow finished;
  if (outcome.status == JobStatus::kOk) {
    finished.result = std::move(result);
  } else {
    finished.result = tracker::EmptyWindowResult(job);
    finished.failed = true;
    finished.error = outcome.error;
  }
  {
    std::lock_guard<std::mutex> lock(results_mu_);
    results_.emplace(job.window_id, std::move(finished));
  }
  results_cv_.notify_all();
}

void Pipeline::FinalizerLoop() {
  std::vector<tracker::Frame3D> frames;
  while (std::optional<Step> step = steps_.Pop()) {
    frames.clear();
    switch (step->kind) {
      case Step::Kind::kClosedFrame:
        finalizer_.AddClosedFrame(step->closed);
        if (provisional_) {
          EmitProvisional(
              provisional_->Estimate(step->closed.frame, step->closed.utime, step->closed.views));
        }
        break;
      case Step::Kind::kWindow: {
        FinishedWindow finished;
        {
          std::unique_lock<std::mutex> lock(results_mu_);
          results_cv_.wait(lock, [&] { return results_.count(step->window_id) > 0; });
          auto node = results_.extract(step->window_id);
          finished = std::move(node.mapped());
        }
        finalizer_.Finalize(finished.result, &frames);
        if (provisional_) provisional_->OnLinked(finalizer_.linker());
        const std::int64_t latency_us = clock_.NowMicros() - step->close_time_us;
        {
          std::lock_guard<std::mutex> lock(status_mu_);
          stats_.windows_processed = finalizer_.counters().windows_processed;
          stats_.tracks_born = finalizer_.counters().tracks_born;
          stats_.tracks_revived = finalizer_.counters().tracks_revived;
          gallery_memory_.SetLinker(finalizer_.counters().gallery_bytes);
          stats_.gallery_bytes = gallery_memory_.total();
          next_track_id_ = finalizer_.linker().next_id();
          if (finished.failed) {
            ++windows_failed_;
            last_failure_ = "window " + std::to_string(step->window_id) + ": " + finished.error;
          }
          ++latency_.count;
          latency_.last_us = latency_us;
          latency_.max_us = std::max(latency_.max_us, latency_us);
          latency_.sum_us += latency_us;
          if (latency_samples_.size() >= kMaxLatencySamples) {
            latency_samples_.erase(latency_samples_.begin());
          }
          latency_samples_.push_back(latency_us);
        }
        Emit(&frames);
        break;
      }
      case Step::Kind::kStreamEnd:
        finalizer_.EndStream(&frames);
        if (provisional_) provisional_->EndStream();
        Emit(&frames);
        break;
      case Step::Kind::kFlushDone: {
        {
          std::lock_guard<std::mutex> lock(flush_mu_);
          flush_done_ = step->flush_ticket;
        }
        flush_cv_.notify_all();
        break;
      }
      case Step::Kind::kStop:
        return;
    }
  }
}

void Pipeline::Emit(std::vector<tracker::Frame3D>* frames) {
  if (frames->empty()) return;
  {
    std::lock_guard<std::mutex> lock(status_mu_);
    stats_.frames_finalized = finalizer_.counters().frames_finalized;
  }
  for (tracker::Frame3D& frame : *frames) {
    try {
      on_frame_(std::move(frame));
    } catch (...) {
      std::lock_guard<std::mutex> lock(status_mu_);
      ++output_callback_errors_;
    }
  }
}

void Pipeline::EmitProvisional(tracker::Frame3D frame) {
  try {
    on_provisional_(std::move(frame));
  } catch (...) {
    std::lock_guard<std::mutex> lock(status_mu_);
    ++output_callback_errors_;
  }
}

PipelineStatus Pipeline::Status() const {
  PipelineStatus s;
  s.reorder_depth = reorder_.size();
  s.finalizer_queue_depth = steps_.size();
  {
    std::lock_guard<std::mutex> lock(results_mu_);
    s.results_waiting = results_.size();
  }
  s.executor = executor_->stats();
  s.cameras.resize(static_cast<std::size_t>(rig_.size()));
  for (std::size_t c = 0; c < s.cameras.size(); ++c) {
    s.cameras[c].camera_id = rig_.camera(static_cast<int>(c)).id;
    s.cameras[c].queue_depth = camera_queues_[c]->depth();
    s.cameras[c].frames_dropped = camera_queues_[c]->dropped();
    s.camera_frames_dropped += s.cameras[c].frames_dropped;
  }
  std::lock_guard<std::mutex> lock(status_mu_);
  s.tracker = stats_;
  s.next_track_id = next_track_id_;
  for (std::size_t c = 0; c < s.cameras.size(); ++c) {
    s.cameras[c].frames_processed = camera_counters_[c].frames_processed;
    s.cameras[c].detections_rejected = camera_counters_[c].detections_rejected;
    s.cameras[c].embeddings_dropped = camera_counters_[c].embeddings_dropped;
  }
  s.windows_submitted = windows_submitted_;
  s.windows_failed = windows_failed_;
  s.last_failure = last_failure_;
  s.output_callback_errors = output_callback_errors_;
  s.window_latency = latency_;
  return s;
}

std::vector<std::int64_t> Pipeline::TakeWindowLatencies() {
  std::lock_guard<std::mutex> lock(status_mu_);
  std::vector<std::int64_t> out;
  out.swap(latency_samples_);
  return out;
}

}  // namespace mvtrack::pipeline
