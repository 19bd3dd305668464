// The threaded Pipeline against the single-threaded Tracker: bit-identical output whatever the
// executor and worker count, clean drain on Stop, overflow drops, failed jobs, latency.

#include "pipeline/pipeline.h"

#include <catch2/catch.hpp>
#include <functional>
#include <latch>
#include <mutex>
#include <stdexcept>

#include "sim/synthetic_scene.h"
#include "tracker/frame3d_equal.h"

namespace mvtrack::pipeline {
namespace {

// One input event: a camera-frame, or an end of stream (Tracker::Flush / Pipeline::Flush).
struct Input {
  bool flush = false;
  core::CameraFrame frame;
};

// 4 cameras x 5 walking people x 300 frames with 2D poses, misses, false positives, keypoint
// dropout and occlusion.
const sim::Scene& BigScene() {
  static const sim::Scene scene = [] {
    sim::SceneOptions o;
    o.seed = 2024;
    o.num_cameras = 4;
    o.num_people = 5;
    o.num_frames = 300;
    o.poses = true;
    o.miss_rate = 0.1;
    o.false_positives_per_frame = 0.3;
    o.keypoint_dropout = 0.05;
    o.pixel_noise_px = 1.5;
    return sim::GenerateScene(o);
  }();
  return scene;
}

// The scene as a live input would deliver it, with every kind of irregularity: camera order
// rotating per frame, duplicate / unknown-camera / stale camera-frames (rejected), a 6-frame gap,
// a jump of 5000 frames (re-anchor) and an explicit end of stream followed by a new stream.
std::vector<Input> IrregularInput(const sim::Scene& scene) {
  std::vector<Input> in;
  const std::size_t n = scene.detections.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (i >= 100 && i < 106) continue;  // gap
    if (i == 220) in.push_back(Input{true, {}});
    const auto& cams = scene.detections[i];
    for (std::size_t k = 0; k < cams.size(); ++k) {
      core::CameraFrame cf = cams[(k + i) % cams.size()];
      if (i >= 150 && i < 220) cf.frame += 5000;  // re-anchor at frame 150
      if (i >= 220) cf.frame += 2000;             // older than 5150+, fine after the flush
      in.push_back(Input{false, cf});
      if (k == 0 && i % 37 == 3) in.push_back(Input{false, cf});  // duplicate camera
      if (k == 0 && i % 41 == 7) {
        core::CameraFrame unknown = cf;
        unknown.camera_id = 99;
        in.push_back(Input{false, unknown});
      }
      if (k == 1 && i % 43 == 11) {
        core::CameraFrame stale = cf;
        stale.frame -= 1;
        in.push_back(Input{false, stale});
      }
    }
  }
  return in;
}

// Plain input: every camera-frame in scene order.
std::vector<Input> PlainInput(const sim::Scene& scene, std::size_t frames) {
  std::vector<Input> in;
  for (std::size_t i = 0; i < frames && i < scene.detections.size(); ++i) {
    for (const core::CameraFrame& cf : scene.detections[i]) in.push_back(Input{false, cf});
  }
  return in;
}

tracker::TrackerOptions PoseOptions() {
  tracker::TrackerOptions o;
  o.mode = tracker::InputMode::kPoses;
  return o;
}

struct RunOutput {
  std::vector<tracker::Frame3D> frames;
  std::vector<tracker::Frame3D> provisional;        // with `provisional` only
  std::vector<tracker::FrameRejection> rejections;  // one per camera-frame input
  tracker::TrackerStats stats;
};

RunOutput RunTracker(const sim::Scene& scene,
                     const tracker::TrackerOptions& options,
                     const std::vector<Input>& input,
                     bool provisional = false) {
  std::string why;
  auto t = tracker::Tracker::Create(geometry::CameraRig(scene.cameras), options, &why, provisional);
  INFO(why);
  REQUIRE(t);
  RunOutput out;
  for (const Input& in : input) {
    if (in.flush) {
      for (auto& f : t->Flush()) out.frames.push_back(std::move(f));
      continue;
    }
    tracker::AddResult r = t->Add(in.frame);
    out.rejections.push_back(r.rejection);
    for (auto& f : r.finalized) out.frames.push_back(std::move(f));
  }
  for (auto& f : t->Flush()) out.frames.push_back(std::move(f));
  out.provisional = t->TakeProvisional();
  out.stats = t->stats();
  return out;
}

// Collects the pipeline's output (the callback runs on the finalizer thread).
struct Collector {
  std::mutex mu;
  std::vector<tracker::Frame3D> frames;
  std::vector<tracker::Frame3D> provisional;
  Pipeline::FrameCallback Callback() {
    return [this](tracker::Frame3D f) {
      std::lock_guard<std::mutex> lock(mu);
      frames.push_back(std::move(f));
    };
  }
  Pipeline::FrameCallback ProvisionalCallback() {
    return [this](tracker::Frame3D f) {
      std::lock_guard<std::mutex> lock(mu);
      provisional.push_back(std::move(f));
    };
  }
};

std::unique_ptr<Pipeline> MakePipeline(const sim::Scene& scene,
                                       const tracker::TrackerOptions& options,
                                       const PipelineOptions& pipeline_options,
                                       std::unique_ptr<Executor> executor,
                                       const Clock& clock,
                                       Collector* collector,
                                       bool provisional = false) {
  std::string why;
  auto p =
      Pipeline::Create(geometry::CameraRig(scene.cameras),
                       options,
                       pipeline_options,
                       std::move(executor),
                       clock,
                       collector->Callback(),
                       &why,
                       provisional ? collector->ProvisionalCallback() : Pipeline::FrameCallback());
  INFO(why);
  REQUIRE(p);
  return p;
}

struct PipelineRun {
  RunOutput output;
  PipelineStatus status;
};

PipelineRun RunPipeline(const sim::Scene& scene,
                        const tracker::TrackerOptions& options,
                        const PipelineOptions& pipeline_options,
                        std::unique_ptr<Executor> executor,
                        const std::vector<Input>& input,
                        bool provisional = false) {
  ManualClock clock;
  Collector collector;
  auto p = MakePipeline(
      scene, options, pipeline_options, std::move(executor), clock, &collector, provisional);
  PipelineRun run;
  for (const Input& in : input) {
    if (in.flush) {
      REQUIRE(p->Flush());
      continue;
    }
    const SubmitResult r = p->Submit(in.frame);
    REQUIRE(r.status != SubmitStatus::kStopped);
    run.output.rejections.push_back(
        r.status == SubmitStatus::kAccepted ? tracker::FrameRejection::kNone : r.rejection);
  }
  p->Stop();
  run.status = p->Status();
  run.output.frames = std::move(collector.frames);
  run.output.provisional = std::move(collector.provisional);
  run.output.stats = run.status.tracker;
  return run;
}

std::unique_ptr<Executor> MakeExecutor(int workers) {
  if (workers == 0) return std::make_unique<InlineExecutor>();
  return std::make_unique<ThreadPoolExecutor>(ThreadPoolOptions{workers, 4});
}

// The Tracker's output on the irregular input (computed once).
const RunOutput& Reference() {
  static const RunOutput reference =
      RunTracker(BigScene(), PoseOptions(), IrregularInput(BigScene()));
  return reference;
}

void CheckIdenticalToTracker(int workers, const PipelineOptions& pipeline_options) {
  const RunOutput& expected = Reference();
  REQUIRE(expected.stats.reanchors == 1);
  REQUIRE(expected.stats.camera_frames_rejected > 10);
  REQUIRE(expected.stats.tracks_born >= 5);
  const PipelineRun run = RunPipeline(BigScene(),
                                      PoseOptions(),
                                      pipeline_options,
                                      MakeExecutor(workers),
                                      IrregularInput(BigScene()));
  const std::string diff = testing::FirstDifference(expected.frames, run.output.frames);
  INFO(diff);
  CHECK(diff.empty());
  CHECK(run.output.rejections == expected.rejections);
  const std::string stats_diff = testing::StatsDifference(expected.stats, run.output.stats);
  INFO(stats_diff);
  CHECK(stats_diff.empty());
  CHECK(run.status.camera_frames_dropped == 0);
  CHECK(run.status.windows_failed == 0);
  CHECK(run.status.windows_submitted == expected.stats.windows_processed);
  CHECK(run.status.window_latency.count == expected.stats.windows_processed);
  CHECK(run.status.executor.completed == run.status.windows_submitted);
  std::int64_t processed = 0;
  for (const CameraStatus& c : run.status.cameras) processed += c.frames_processed;
  CHECK(processed == expected.stats.camera_frames_accepted);
}

PipelineOptions Lossless() {
  PipelineOptions o;
  o.camera_overflow = OverflowPolicy::kBlock;
  return o;
}

// Tiny queues everywhere: back-pressure on every stage boundary.
PipelineOptions LosslessTiny() {
  PipelineOptions o = Lossless();
  o.camera_queue_capacity = 1;
  o.reorder_capacity = 3;
  o.finalizer_queue_capacity = 2;
  return o;
}

// The provisional layer (tracker::ProvisionalEstimator) is made in the order of the builder's
// output on both, so it is identical too, and asking for it changes nothing in the final output.
TEST_CASE("provisional layer: pipeline = Tracker at any worker count, final output unchanged",
          "[threads][pipeline]") {
  const RunOutput expected =
      RunTracker(BigScene(), PoseOptions(), IrregularInput(BigScene()), /*provisional=*/true);
  REQUIRE(testing::FirstDifference(Reference().frames, expected.frames).empty());
  // One provisional frame per closed frame, in increasing order within each stream; tracks in
  // most of them.
  REQUIRE(expected.provisional.size() >= expected.frames.size());
  std::size_t with_tracks = 0;
  for (const tracker::Frame3D& f : expected.provisional) with_tracks += f.tracks.empty() ? 0 : 1;
  INFO(with_tracks << " of " << expected.provisional.size() << " provisional frames with tracks");
  CHECK(with_tracks * 10 >= expected.provisional.size() * 6);  // each stream starts empty
  for (const int workers : {0, 2, 8}) {
    INFO("workers " << workers);
    const PipelineRun run = RunPipeline(BigScene(),
                                        PoseOptions(),
                                        workers == 8 ? LosslessTiny() : Lossless(),
                                        MakeExecutor(workers),
                                        IrregularInput(BigScene()),
                                        /*provisional=*/true);
    const std::string diff = testing::FirstDifference(expected.frames, run.output.frames);
    INFO(diff);
    CHECK(diff.empty());
    const std::string provisional_diff =
        testing::FirstDifference(expected.provisional, run.output.provisional);
    INFO(provisional_diff);
    CHECK(provisional_diff.empty());
  }
}

TEST_CASE("pipeline with InlineExecutor = Tracker, bit for bit", "[threads][pipeline]") {
  CheckIdenticalToTracker(0, Lossless());
}

TEST_CASE("pipeline with 1 worker = Tracker, bit for bit", "[threads][pipeline]") {
  CheckIdenticalToTracker(1, Lossless());
}

TEST_CASE("pipeline with 2 workers = Tracker, bit for bit", "[threads][pipeline]") {
  CheckIdenticalToTracker(2, Lossless());
}

// Camera threads serve several cameras each, taking the oldest item first: one thread for all
// four cameras with a reorder look-ahead of 3 must neither deadlock nor change the output; nor
// must a thread per camera.
TEST_CASE("pipeline with one camera thread for all cameras, tiny queues = Tracker, bit for bit",
          "[threads][pipeline]") {
  PipelineOptions o = LosslessTiny();
  o.camera_threads = 1;
  CheckIdenticalToTracker(2, o);
  o.camera_threads = 3;  // uneven: cameras 0 and 3 share a thread
  CheckIdenticalToTracker(2, o);
  o = Lossless();
  o.camera_threads = 64;  // more than cameras: one per camera
  CheckIdenticalToTracker(2, o);
}

TEST_CASE("pipeline with 8 workers and tiny queues = Tracker, bit for bit", "[threads][pipeline]") {
  CheckIdenticalToTracker(8, LosslessTiny());
}

// An Executor that runs `hook(job_index)` inside each job, before the job itself (so a throwing
// hook makes a failed job), on an InlineExecutor.
class HookedExecutor final : public Executor {
 public:
  explicit HookedExecutor(std::function<void(std::uint64_t)> hook) : hook_(std::move(hook)) {}
  bool Submit(Job job, Completion completion) override {
    const std::uint64_t index = next_index_++;  // Submit runs on the scheduler thread only
    return inner_.Submit(
        [this, index, job = std::move(job)](int worker) {
          hook_(index);
          job(worker);
        },
        std::move(completion));
  }
  void Drain() override { inner_.Drain(); }
  void Stop() override { inner_.Stop(); }
  int num_workers() const override { return inner_.num_workers(); }
  ExecutorStats stats() const override { return inner_.stats(); }

 private:
  std::function<void(std::uint64_t)> hook_;
  std::uint64_t next_index_ = 0;
  InlineExecutor inner_;
};

sim::Scene BoxScene() {
  sim::SceneOptions o;
  o.seed = 99;
  o.num_cameras = 4;
  o.num_people = 4;
  o.num_frames = 300;
  o.poses = false;
  o.miss_rate = 0.05;
  o.false_positives_per_frame = 0.2;
  return sim::GenerateScene(o);
}

TEST_CASE("Stop in the middle of a frame drains like Tracker::Flush", "[threads][pipeline]") {
  const sim::Scene scene = BoxScene();
  std::vector<Input> input = PlainInput(scene, 137);
  input.resize(input.size() - 2);  // stop after 2 of the 4 cameras of frame 136
  const RunOutput expected = RunTracker(scene, tracker::TrackerOptions{}, input);
  REQUIRE(expected.stats.tracks_born > 0);

  ManualClock clock;
  Collector collector;
  auto p = MakePipeline(
      scene, tracker::TrackerOptions{}, Lossless(), MakeExecutor(2), clock, &collector);
  for (const Input& in : input) REQUIRE(p->Submit(in.frame).status == SubmitStatus::kAccepted);
  p->Stop();
  const std::string diff = testing::FirstDifference(expected.frames, collector.frames);
  INFO(diff);
  CHECK(diff.empty());
  REQUIRE(collector.frames.size() == 137);  // every frame once, the partial one included
  for (std::size_t i = 0; i < collector.frames.size(); ++i) {
    CHECK(collector.frames[i].frame == scene.detections[i][0].frame);
  }
  // Drained: nothing left anywhere, further input refused.
  const PipelineStatus s = p->Status();
  for (const CameraStatus& c : s.cameras) CHECK(c.queue_depth == 0);
  CHECK(s.reorder_depth == 0);
  CHECK(s.finalizer_queue_depth == 0);
  CHECK(s.results_waiting == 0);
  CHECK(s.executor.queued == 0);
  CHECK(s.executor.running == 0);
  CHECK(s.windows_submitted == expected.stats.windows_processed);
  CHECK(s.tracker.frames_finalized == 137);
  CHECK(p->Submit(scene.detections[140][0]).status == SubmitStatus::kStopped);
  CHECK_FALSE(p->Flush());
  p->Stop();  // idempotent
}

TEST_CASE("camera queue overflow drops the oldest camera-frames, counts them, keeps frames",
          "[threads][pipeline]") {
  const sim::Scene scene = BoxScene();
  const std::vector<Input> input = PlainInput(scene, 300);
  PipelineOptions po;
  po.camera_overflow = OverflowPolicy::kDropOldest;
  po.camera_queue_capacity = 2;
  po.reorder_capacity = 8;
  // The first window job blocks the scheduler until every camera-frame has been submitted.
  std::latch release(1);
  auto executor = std::make_unique<HookedExecutor>([&release](std::uint64_t job) {
    if (job == 0) release.wait();
  });
  ManualClock clock;
  Collector collector;
  auto p =
      MakePipeline(scene, tracker::TrackerOptions{}, po, std::move(executor), clock, &collector);
  for (const Input& in : input) REQUIRE(p->Submit(in.frame).status == SubmitStatus::kAccepted);
  const PipelineStatus stalled = p->Status();
  release.count_down();
  p->Stop();
  const PipelineStatus s = p->Status();

  // The scheduler stalled on the first window, emitted when the first camera-frame of frame ν
  // arrived (sequence number ν·C). Beyond it at most reorder_capacity outputs wait for the
  // scheduler, and each camera holds one camera-frame in hand plus camera_queue_capacity
  // queued; every other camera-frame must have been dropped.
  const auto cams = static_cast<std::int64_t>(scene.cameras.size());
  const std::int64_t total = static_cast<std::int64_t>(input.size());
  const std::int64_t consumed = 30 * cams + 1;
  const std::int64_t bound =
      total - consumed - po.reorder_capacity - cams * (1 + po.camera_queue_capacity);
  INFO("dropped " << s.camera_frames_dropped << ", bound " << bound);
  CHECK(s.camera_frames_dropped >= bound);
  CHECK(stalled.camera_frames_dropped == s.camera_frames_dropped);  // all drops happened then
  std::int64_t processed = 0;
  for (const CameraStatus& c : s.cameras) {
    processed += c.frames_processed;
    CHECK(c.frames_dropped > 0);
    CHECK(c.queue_depth == 0);
  }
  CHECK(processed + s.camera_frames_dropped == total);
  CHECK(s.tracker.camera_frames_accepted == total);
  // Dropping loses detections, never frames: every frame is output once, in order.
  REQUIRE(collector.frames.size() == scene.detections.size());
  for (std::size_t i = 0; i < collector.frames.size(); ++i) {
    CHECK(collector.frames[i].frame == scene.detections[i][0].frame);
  }
  const RunOutput lossless = RunTracker(scene, tracker::TrackerOptions{}, input);
  CHECK(s.tracker.detections_used < lossless.stats.detections_used);
}

TEST_CASE("a failing window job is counted and links as an empty window", "[threads][pipeline]") {
  const sim::Scene scene = BoxScene();
  const std::vector<Input> input = PlainInput(scene, 300);
  const RunOutput expected = RunTracker(scene, tracker::TrackerOptions{}, input);
  auto executor = std::make_unique<HookedExecutor>([](std::uint64_t job) {
    if (job == 2) throw std::runtime_error("injected failure");
  });
  ManualClock clock;
  Collector collector;
  auto p = MakePipeline(
      scene, tracker::TrackerOptions{}, Lossless(), std::move(executor), clock, &collector);
  for (const Input& in : input) REQUIRE(p->Submit(in.frame).status == SubmitStatus::kAccepted);
  p->Stop();
  const PipelineStatus s = p->Status();
  CHECK(s.camera_frames_dropped == 0);
  CHECK(s.windows_failed == 1);
  CHECK_THAT(s.last_failure, Catch::Contains("injected failure"));
  CHECK_THAT(s.last_failure, Catch::Contains("window 2"));
  REQUIRE(collector.frames.size() == expected.frames.size());
  // Window 2 = [40, 70) finalizes [45, 65): before it the output is the Tracker's, inside it
  // there are no tracks (the Tracker has some), and every frame is still output in order.
  const tracker::TrackerOptions o;
  const FrameIndex from = 2 * o.window_step + (o.window_size - o.window_step) / 2;
  const FrameIndex to = from + o.window_step;
  std::vector<tracker::Frame3D> head_expected, head_actual;
  std::size_t expected_tracks_in_failed = 0;
  for (std::size_t i = 0; i < collector.frames.size(); ++i) {
    const tracker::Frame3D& f = collector.frames[i];
    CHECK(f.frame == expected.frames[i].frame);
    if (f.frame < from) {
      head_expected.push_back(expected.frames[i]);
      head_actual.push_back(f);
    } else if (f.frame < to) {
      CHECK(f.tracks.empty());
      expected_tracks_in_failed += expected.frames[i].tracks.size();
    }
  }
  INFO(testing::FirstDifference(head_expected, head_actual));
  CHECK(testing::FirstDifference(head_expected, head_actual).empty());
  CHECK(expected_tracks_in_failed > 0);
}

TEST_CASE("window latency is measured with the pipeline's clock, callback errors are counted",
          "[threads][pipeline]") {
  const sim::Scene scene = BoxScene();
  const std::vector<Input> input = PlainInput(scene, 120);
  ManualClock clock(1000000);
  // Each job takes 1000 µs of manual time.
  auto executor =
      std::make_unique<HookedExecutor>([&clock](std::uint64_t) { clock.AdvanceMicros(1000); });
  std::string why;
  std::int64_t delivered = 0;  // written on the finalizer thread, read after Stop
  auto p = Pipeline::Create(
      geometry::CameraRig(scene.cameras),
      tracker::TrackerOptions{},
      Lossless(),
      std::move(executor),
      clock,
      [&delivered](tracker::Frame3D f) {
        ++delivered;
        if (f.frame % 2 == 1) throw std::runtime_error("consumer bug");
      },
      &why);
  REQUIRE(p);
  for (const Input& in : input) REQUIRE(p->Submit(in.frame).status == SubmitStatus::kAccepted);
  p->Stop();
  const PipelineStatus s = p->Status();
  CHECK(delivered == 120);
  CHECK(s.output_callback_errors == 60);
  CHECK(s.tracker.frames_finalized == 120);
  REQUIRE(s.window_latency.count == s.tracker.windows_processed);
  REQUIRE(s.window_latency.count > 0);
  CHECK(s.window_latency.last_us >= 1000);
  CHECK(s.window_latency.max_us >= 1000);
  CHECK(s.window_latency.sum_us >= 1000 * s.window_latency.count);
  CHECK(s.window_latency.mean_us() >= 1000.0);
}

TEST_CASE("Pipeline::Create refuses bad configurations with a reason", "[unit][pipeline]") {
  const sim::Scene scene = BoxScene();
  ManualClock clock;
  std::string why;
  auto sink = [](tracker::Frame3D) {};
  CHECK(Pipeline::Create(geometry::CameraRig({scene.cameras[0]}),
                         {},
                         {},
                         std::make_unique<InlineExecutor>(),
                         clock,
                         sink,
                         &why) == nullptr);
  CHECK_THAT(why, Catch::Contains("at least 2"));
  PipelineOptions bad;
  bad.reorder_capacity = 0;
  CHECK(Pipeline::Create(geometry::CameraRig(scene.cameras),
                         {},
                         bad,
                         std::make_unique<InlineExecutor>(),
                         clock,
                         sink,
                         &why) == nullptr);
  CHECK_THAT(why, Catch::Contains("reorder_capacity"));
  bad = PipelineOptions();
  bad.camera_threads = -1;
  CHECK(Pipeline::Create(geometry::CameraRig(scene.cameras),
                         {},
                         bad,
                         std::make_unique<InlineExecutor>(),
                         clock,
                         sink,
                         &why) == nullptr);
  CHECK_THAT(why, Catch::Contains("camera_threads"));
  tracker::TrackerOptions bad_tracker;
  bad_tracker.window_step = 0;
  CHECK(Pipeline::Create(geometry::CameraRig(scene.cameras),
                         bad_tracker,
                         {},
                         std::make_unique<InlineExecutor>(),
                         clock,
                         sink,
                         &why) == nullptr);
  CHECK_THAT(why, Catch::Contains("window_step"));
  CHECK(Pipeline::Create(geometry::CameraRig(scene.cameras), {}, {}, nullptr, clock, sink, &why) ==
        nullptr);
  CHECK_THAT(why, Catch::Contains("executor"));
  CHECK(Pipeline::Create(geometry::CameraRig(scene.cameras),
                         {},
                         {},
                         std::make_unique<InlineExecutor>(),
                         clock,
                         {},
                         &why) == nullptr);
  CHECK_THAT(why, Catch::Contains("callback"));
}

}  // namespace
}  // namespace mvtrack::pipeline
