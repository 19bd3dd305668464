#include "service/service.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <mvtrack/camera_status_t.hpp>
#include <mvtrack/tracker_status_t.hpp>
#include <random>
#include <utility>

#include "config/tracker_options.h"
#include "geometry/camera_rig.h"
#include "pipeline/executor.h"
#include "service/status_check.h"
#include "transport/channels.h"
#include "transport/codec.h"
#include "transport/log_io.h"

namespace mvtrack::service {
namespace {

// Bounds on bookkeeping that grows with the input (memory stays bounded whatever arrives).
constexpr std::size_t kMaxReleaseTimes = 4096;
constexpr std::size_t kMaxLatencySamples = 100000;

std::int64_t Seconds(double s) { return static_cast<std::int64_t>(std::llround(s * 1e6)); }

std::vector<std::string> RestartOnlyChanges(const DaemonConfig& a, const DaemonConfig& b) {
  std::vector<std::string> changed;
  auto check = [&](bool differs, const char* key) {
    if (differs) changed.emplace_back(key);
  };
  std::string ids_a, ids_b;
  for (const auto& c : a.cameras) ids_a += std::to_string(c.id) + ",";
  for (const auto& c : b.cameras) ids_b += std::to_string(c.id) + ",";
  check(a.zone != b.zone, "zone");
  check(a.calibration_path != b.calibration_path || ids_a != ids_b, "cameras");
  check(a.input_url != b.input_url, "input.lcm_url");
  check(a.channel_mode != b.channel_mode, "input.channels");
  check(a.max_message_bytes != b.max_message_bytes, "input.max_message_bytes");
  check(a.max_detections_per_message != b.max_detections_per_message, "input.max_detections");
  check(a.lcm_queue_capacity != b.lcm_queue_capacity, "input.lcm_queue_capacity");
  check(a.output_url != b.output_url, "output.lcm_url");
  check(a.tracks_channel != b.tracks_channel, "output.tracks_channel");
  check(a.status_channel != b.status_channel, "output.status_channel");
  check(a.provisional_channel != b.provisional_channel, "output.provisional_channel");
  const SyncOptions& s = a.sync;
  const SyncOptions& t = b.sync;
  check(s.mode != t.mode || s.tolerance_us != t.tolerance_us || s.deadline_us != t.deadline_us ||
            s.silent_after_us != t.silent_after_us || s.max_future_us != t.max_future_us ||
            s.max_frame_ahead != t.max_frame_ahead ||
            s.clock_tolerance_us != t.clock_tolerance_us ||
            s.max_frame_offset != t.max_frame_offset ||
            s.min_frame_interval_us != t.min_frame_interval_us ||
            s.resync_after_rejections != t.resync_after_rejections ||
            s.max_pending_frames != t.max_pending_frames || s.idle_flush_s != t.idle_flush_s,
        "sync");
  check(a.workers != b.workers || a.job_queue_capacity != b.job_queue_capacity, "threads");
  check(a.camera_queue_capacity != b.camera_queue_capacity ||
            a.camera_overflow != b.camera_overflow || a.reorder_capacity != b.reorder_capacity ||
            a.finalizer_queue_capacity != b.finalizer_queue_capacity,
        "queues");
  return changed;
}

std::vector<CameraId> CameraIds(const DaemonConfig& config) {
  std::vector<CameraId> ids;
  for (const geometry::CameraModel& c : config.cameras) ids.push_back(c.id);
  return ids;
}

}  // namespace

std::unique_ptr<Service> Service::Create(DaemonConfig config,
                                         ServiceHooks hooks,
                                         std::string* why) {
  std::unique_ptr<Service> s(new Service(std::move(config), std::move(hooks)));
  std::string reason;
  s->pipeline_ = s->MakePipeline(s->config_.tracker, &reason);
  if (!s->pipeline_) {
    if (why != nullptr) *why = reason;
    s->stopped_ = true;  // nothing to stop
    return nullptr;
  }
  if (!s->config_.state_directory.empty()) {
    s->reservation_.emplace();
    if (!s->reservation_->Open(s->config_.state_directory, s->config_.id_block, &reason)) {
      if (why != nullptr) *why = "state: " + reason;
      return nullptr;
    }
    s->id_offset_ = s->reservation_->first_id() - 1;
    s->reserved_end_.store(s->reservation_->reserved_end());
    spdlog::info("track ids start at {} (reserved below {} in {})",
                 s->reservation_->first_id(),
                 s->reservation_->reserved_end(),
                 s->config_.state_directory);
  }
  if (!s->hooks_.record_path.empty()) {
    s->record_ = transport::LogWriter::Open(s->hooks_.record_path, &reason);
    if (!s->record_) {
      if (why != nullptr) *why = "--record: " + reason;
      return nullptr;
    }
  }
  return s;
}

Service::Service(DaemonConfig config, ServiceHooks hooks)
    : config_(std::move(config)),
      hooks_(std::move(hooks)),
      config_hash_(DaemonConfigHash(config_)),
      wall_clock_(hooks_.wall_clock != nullptr ? hooks_.wall_clock : &system_clock_),
      start_us_(wall_clock_->NowMicros()),
      instance_id_(RandomInstanceId()),
      sync_(CameraIds(config_), config_.sync),
      limiter_(Seconds(config_.log_repeat_interval_s)) {
  for (std::size_t i = 0; i < config_.cameras.size(); ++i) {
    camera_index_[config_.cameras[i].id] = static_cast<int>(i);
  }
  inputs_.resize(config_.cameras.size());
  output_layout_ = config_.tracker.mode == tracker::InputMode::kPoses
                       ? config_.tracker.layout
                       : core::KeypointLayoutId::kNone;
  period_start_us_ = start_us_;
  next_status_us_ = start_us_ + Seconds(config_.status_period_s);
  last_message_us_ = start_us_;
  if (!config_.site_path.empty()) analytics_.emplace(config_.site);
}

Service::~Service() { Stop(); }

std::unique_ptr<pipeline::Pipeline> Service::MakePipeline(const tracker::TrackerOptions& options,
                                                          std::string* why) {
  std::string reason;
  geometry::CameraRig rig(config_.cameras, &reason);
  if (!rig.ok()) {
    *why = "calibration: " + reason;
    return nullptr;
  }
  pipeline::ThreadPoolOptions pool;
  pool.num_workers = config_.EffectiveWorkers();
  pool.queue_capacity = config_.job_queue_capacity;
  if (!pool.Validate(&reason)) {
    *why = "threads: " + reason;
    return nullptr;
  }
  pipeline::PipelineOptions po;
  po.camera_queue_capacity = config_.camera_queue_capacity;
  po.camera_overflow = config_.camera_overflow;
  po.reorder_capacity = config_.reorder_capacity;
  po.finalizer_queue_capacity = config_.finalizer_queue_capacity;
  return pipeline::Pipeline::Create(
      std::move(rig),
      options,
      po,
      std::make_unique<pipeline::ThreadPoolExecutor>(pool),
      steady_clock_,
      [this](tracker::Frame3D frame) { OnFrame(std::move(frame)); },
      why,
      config_.provisional_channel.empty()
          ? pipeline::Pipeline::FrameCallback()
          : pipeline::Pipeline::FrameCallback(
                [this](tracker::Frame3D frame) { OnProvisional(std::move(frame)); }));
}

void Service::Warn(const std::string& kind, const std::string& message) {
  if (const std::optional<std::int64_t> suppressed = limiter_.Allow(kind, Now())) {
    if (*suppressed > 0) {
      spdlog::warn("{} ({} similar message(s) suppressed)", message, *suppressed);
    } else {
      spdlog::warn("{}", message);
    }
  }
}

void Service::Record(const std::string& channel,
                     const std::uint8_t* data,
                     std::size_t size,
                     std::int64_t time_us) {
  if (!record_) return;
  std::string why;
  if (!record_->Write(channel, time_us, data, size, &why)) {
    spdlog::error("record log: {}; recording stops", why);
    record_.reset();
    std::lock_guard<std::mutex> lock(mu_);
    ++counters_.record_errors;
  }
}

void Service::Publish(const std::string& channel,
                      const std::vector<std::uint8_t>& data,
                      std::int64_t time_us) {
  std::lock_guard<std::mutex> lock(out_mu_);
  if (hooks_.publish) hooks_.publish(channel, data);
  Record(channel, data.data(), data.size(), time_us);
}

void Service::OnMessage(const std::string& channel, const std::uint8_t* data, std::size_t size) {
  if (stopped_) return;
  const std::int64_t now = Now();
  {
    std::lock_guard<std::mutex> lock(out_mu_);
    Record(channel, data, size, now);
  }
  if (!any_message_ || now - last_message_us_ >= kNoOutputAfterUs) input_since_us_ = now;
  any_message_ = true;
  last_message_us_ = now;
  idle_flushed_ = false;
  {
    std::lock_guard<std::mutex> lock(mu_);
    ++counters_.messages;
  }
  if (!transport::IsDetectionsChannel(channel)) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      ++counters_.foreign_messages;
    }
    Warn("foreign:" + channel, "ignoring a message on channel " + channel);
    return;
  }
  const std::optional<CameraId> channel_camera = transport::CameraIdFromChannel(channel);
  std::optional<int> channel_index;
  if (channel_camera) {
    const auto it = camera_index_.find(*channel_camera);
    if (it != camera_index_.end()) channel_index = it->second;
  }
  transport::DecodeLimits limits;
  limits.max_message_bytes = static_cast<std::size_t>(config_.max_message_bytes);
  limits.max_detections = config_.max_detections_per_message;
  transport::DecodeResult decoded = transport::DecodeCameraDetections(data, size, limits);
  if (!decoded.ok()) {
    const std::string kind = transport::ToString(decoded.status);
    {
      std::lock_guard<std::mutex> lock(mu_);
      ++counters_.decode_errors;
      ++counters_.decode_errors_by_kind[kind];
      if (channel_index) ++inputs_[static_cast<std::size_t>(*channel_index)].decode_errors;
    }
    Warn("decode:" + kind,
         "bad message on " + channel + " (" + std::to_string(size) + " bytes): " + kind + ": " +
             decoded.reason);
    return;
  }
  core::CameraFrame& frame = decoded.frame;
  if (channel_camera && *channel_camera != frame.camera_id) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      ++counters_.channel_mismatches;
      if (channel_index) ++inputs_[static_cast<std::size_t>(*channel_index)].decode_errors;
    }
    Warn("channel-mismatch",
         "message on " + channel + " carries camera_id " + std::to_string(frame.camera_id) +
             "; dropped");
    return;
  }
  const auto known = camera_index_.find(frame.camera_id);
  if (known != camera_index_.end()) {
    const geometry::CameraModel& cam = config_.cameras[static_cast<std::size_t>(known->second)];
    std::lock_guard<std::mutex> lock(mu_);
    CameraInput& in = inputs_[static_cast<std::size_t>(known->second)];
    ++in.received;
    in.last_receive_us = now;
    in.last_utime = frame.utime;
    if (decoded.image_width_px != 0 && decoded.image_height_px != 0 &&
        (decoded.image_width_px != cam.width_px || decoded.image_height_px != cam.height_px)) {
      ++counters_.image_size_mismatches;
    }
  }
  const CameraId camera = frame.camera_id;
  const FrameIndex input_frame = frame.frame;
  SyncResult r = sync_.Add(std::move(frame));
  if (r.rejection == SyncRejection::kNone && config_.sync.mode == SyncMode::kFrameIndex) {
    std::lock_guard<std::mutex> lock(mu_);
    first_receive_us_.try_emplace(input_frame, now);
    while (first_receive_us_.size() > kMaxReleaseTimes) {
      first_receive_us_.erase(first_receive_us_.begin());
    }
  }
  // Per-camera transitions are rate limited like the warnings (a flapping camera must not fill
  // the journal); the counters and status flags carry every one.
  for (const CameraTransition& t : r.transitions) {
    const std::string cam_key = std::to_string(t.camera_id);
    switch (t.kind) {
      case CameraTransition::Kind::kSilence:
        Warn("sync:silence:" + cam_key,
             t.excluded ? "camera " + cam_key +
                              " is silent: excluded from synchronization until it returns"
                        : "camera " + cam_key + " delivers again: included in synchronization");
        break;
      case CameraTransition::Kind::kClock:
        Warn("sync:clock:" + cam_key,
             t.excluded ? "camera " + cam_key + " clock is " + std::to_string(t.offset_us / 1000) +
                              " ms (" + std::to_string(t.offset_frames) +
                              " frames) off the other cameras': CLOCK_OFFSET, its camera-frames "
                              "are rejected until it agrees again (sync.clock_tolerance_us " +
                              std::to_string(config_.sync.clock_tolerance_us) + ")"
                        : "camera " + cam_key + " clock agrees with the other cameras' again (" +
                              std::to_string(t.offset_us / 1000) + " ms): included");
        break;
      case CameraTransition::Kind::kRestart:
        Warn("sync:restart:" + cam_key,
             "camera " + cam_key + " restarted alone (" +
                 std::to_string(config_.sync.resync_after_rejections) +
                 " consecutive out-of-order camera-frames): its time order starts over, the "
                 "other cameras' stream goes on");
        break;
    }
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    ++counters_.camera_frames_decoded;
    if (r.rejection != SyncRejection::kNone) {
      ++counters_.sync_rejected;
      ++counters_.sync_rejections[ToString(r.rejection)];
    }
    if (r.resynced) ++counters_.stream_restarts;
  }
  if (r.resynced) {
    Warn("sync:stream_restart",
         "input stream restarted (more than half of the cameras had " +
             std::to_string(std::min(config_.sync.resync_after_rejections,
                                     FrameSynchronizer::kStreamVoteRejections)) +
             " consecutive camera-frames rejected for their time: the rig's time stepped): "
             "tracks end and a new stream starts");
  }
  if (r.rejection != SyncRejection::kNone) {
    Warn(std::string("sync:") + ToString(r.rejection) + ":" + std::to_string(camera),
         std::string("rejected camera-frame: ") + ToString(r.rejection) + ": " + r.reason);
  }
  Apply(&r.actions);
  const SyncStatus status = sync_.Status();
  std::lock_guard<std::mutex> lock(mu_);
  counters_.sync = status;
}

void Service::Apply(std::vector<SyncAction>* actions) {
  for (SyncAction& a : *actions) {
    if (a.kind == SyncAction::Kind::kEndStream) {
      FlushPipeline();
      continue;
    }
    const FrameIndex frame_index = a.frame.frame;
    const CameraId camera = a.frame.camera_id;
    {
      std::lock_guard<std::mutex> lock(mu_);
      release_us_[frame_index] = Now();
      if (config_.sync.mode == SyncMode::kUtime) first_receive_us_.try_emplace(frame_index, Now());
      while (first_receive_us_.size() > kMaxReleaseTimes) {
        first_receive_us_.erase(first_receive_us_.begin());
      }
      while (release_us_.size() > kMaxReleaseTimes) release_us_.erase(release_us_.begin());
      ++counters_.submitted;
    }
    const pipeline::SubmitResult r = pipeline_->Submit(std::move(a.frame));
    if (r.status == pipeline::SubmitStatus::kRejected) {
      {
        std::lock_guard<std::mutex> lock(mu_);
        ++counters_.gate_rejected;
      }
      Warn(std::string("gate:") + tracker::ToString(r.rejection) + ":" + std::to_string(camera),
           std::string("tracker rejected camera-frame: ") + tracker::ToString(r.rejection) + ": " +
               r.reason);
    }
  }
}

void Service::FlushPipeline() {
  flushing_.store(true, std::memory_order_release);
  pipeline_->Flush();
  flushing_.store(false, std::memory_order_release);
}

// Under mu_: shifts `frame`'s ids into the published id space and returns its processing
// latency (now minus its release); samples its receive -> publish time into `samples` unless a
// flush publishes it. The final layer (`final`) is the frame's last output: its timing entries
// go, and a frame a flush published is counted.
std::int64_t Service::StampOutput(tracker::Frame3D* frame,
                                  std::int64_t now,
                                  bool final,
                                  std::vector<std::int64_t>* samples) {
  std::lock_guard<std::mutex> lock(mu_);
  for (tracker::Track3D& t : frame->tracks) t.id += id_offset_;
  std::int64_t latency = 0;
  const auto it = release_us_.find(frame->frame);
  if (it != release_us_.end()) latency = std::max<std::int64_t>(0, now - it->second);
  const auto first = first_receive_us_.find(frame->frame);
  if (flushing_.load(std::memory_order_acquire)) {
    if (final) ++counters_.frames_published_by_flush;
  } else if (first != first_receive_us_.end() && samples->size() < kMaxReceiveLatencySamples) {
    samples->push_back(std::max<std::int64_t>(0, now - first->second));
  }
  if (final) {
    release_us_.erase(release_us_.begin(), release_us_.upper_bound(frame->frame));
    first_receive_us_.erase(first_receive_us_.begin(), first_receive_us_.upper_bound(frame->frame));
  }
  return latency;
}

void Service::OnFrame(tracker::Frame3D frame) {
  const std::int64_t now = Now();
  const std::int64_t latency =
      StampOutput(&frame, now, /*final=*/true, &counters_.receive_to_publish_us);
  CoverIds(frame);
  const std::vector<std::uint8_t> bytes =
      transport::EncodeTracks(frame, output_layout_, now, latency);
  Publish(config_.tracks_channel, bytes, now);
  if (hooks_.on_frame) hooks_.on_frame(frame, output_layout_);
  if (analytics_) Analyse(frame, now);
  std::lock_guard<std::mutex> lock(mu_);
  ++counters_.frames_published;
  counters_.max_latency_us = std::max(counters_.max_latency_us, latency);
  if (latency_samples_.size() < kMaxLatencySamples) latency_samples_.push_back(latency);
  last_frame_ = frame.frame;
  last_publish_us_ = now;
  active_tracks_ = static_cast<int>(frame.tracks.size());
  confirmed_tracks_ = 0;
  for (const tracker::Track3D& t : frame.tracks) {
    if (t.state != linking::TrackState::kTentative) ++confirmed_tracks_;
    max_published_id_ = std::max(max_published_id_, t.id);
  }
}

void Service::CoverIds(const tracker::Frame3D& frame) {
  TrackId3D frame_max_id = 0;
  for (const tracker::Track3D& t : frame.tracks) frame_max_id = std::max(frame_max_id, t.id);
  if (frame_max_id >= reserved_end_.load(std::memory_order_acquire)) {
    // Never publish an id the state does not cover (the control thread extends it earlier).
    std::string why;
    if (!ExtendReservation(frame_max_id + 1, &why)) {
      spdlog::error("cannot extend the track id reservation: {}", why);
    }
  }
}

void Service::OnProvisional(tracker::Frame3D frame) {
  const std::int64_t now = Now();
  const std::int64_t latency =
      StampOutput(&frame, now, /*final=*/false, &counters_.provisional_receive_to_publish_us);
  CoverIds(frame);
  const std::vector<std::uint8_t> bytes = transport::EncodeTracks(
      frame, output_layout_, now, latency, transport::TracksLayer::kProvisional);
  Publish(config_.provisional_channel, bytes, now);
  if (hooks_.on_provisional) hooks_.on_provisional(frame, output_layout_);
  std::lock_guard<std::mutex> lock(mu_);
  ++counters_.provisional_published;
  // A reload continues above every id published on either layer.
  for (const tracker::Track3D& t : frame.tracks)
    max_published_id_ = std::max(max_published_id_, t.id);
}

void Service::Analyse(const tracker::Frame3D& frame, std::int64_t now) {
  std::vector<analytics::TrackPosition> positions;
  positions.reserve(frame.tracks.size());
  for (const tracker::Track3D& t : frame.tracks) positions.push_back({t.id, t.position.head<2>()});
  std::lock_guard<std::mutex> lock(analytics_mu_);
  const std::vector<analytics::Event> events =
      analytics_->Update(static_cast<double>(frame.utime) * 1e-6, positions);
  analytics_utime_ = frame.utime;
  for (const analytics::Event& e : events) {
    Publish(
        config_.analytics_events_channel,
        transport::EncodeAnalyticsEvent(transport::ToAnalyticsEventMessage(e, config_.site, now)),
        now);
  }
  if (!events.empty()) PublishSiteCounts(now);
  std::lock_guard<std::mutex> counters_lock(mu_);
  counters_.analytics_events_published += static_cast<std::int64_t>(events.size());
}

void Service::PublishSiteCounts(std::int64_t now) {
  transport::SiteCounts counts;
  counts.utime = analytics_utime_;
  counts.publish_utime = now;
  for (const analytics::Region& r : config_.site.regions) counts.region_names.push_back(r.name);
  counts.regions = analytics_->region_counts();
  for (const analytics::Line& l : config_.site.lines) counts.line_names.push_back(l.name);
  counts.lines = analytics_->line_counts();
  Publish(config_.site_counts_channel, transport::EncodeSiteCounts(counts), now);
  std::lock_guard<std::mutex> lock(mu_);
  ++counters_.site_counts_published;
}

bool Service::ExtendReservation(TrackId3D next_id, std::string* why) {
  std::lock_guard<std::mutex> lock(reservation_mu_);
  if (!reservation_) return true;
  const bool ok = reservation_->Extend(next_id, why);
  if (!ok) *why += " (ids stay unique up to " + std::to_string(reservation_->reserved_end()) + ")";
  reserved_end_.store(reservation_->reserved_end(), std::memory_order_release);
  return ok;
}

void Service::Tick() {
  if (stopped_) return;
  const std::int64_t now = Now();
  if (reservation_) {
    TrackId3D offset = 0;
    {
      std::lock_guard<std::mutex> lock(mu_);
      offset = id_offset_;
    }
    std::string why;
    if (!ExtendReservation(offset + pipeline_->Status().next_track_id, &why)) {
      Warn("state:ids", "cannot extend the track id reservation: " + why);
    }
  }
  if (now >= next_status_us_) {
    const std::vector<std::uint8_t> status = BuildStatus();
    Publish(config_.status_channel, status, now);
    {
      std::lock_guard<std::mutex> lock(mu_);
      ++counters_.status_published;
    }
    if (analytics_) {
      std::lock_guard<std::mutex> lock(analytics_mu_);
      PublishSiteCounts(now);
    }
    next_status_us_ = now + Seconds(config_.status_period_s);
  }
  if (config_.sync.idle_flush_s > 0.0 && !idle_flushed_ &&
      now - last_message_us_ >= Seconds(config_.sync.idle_flush_s)) {
    idle_flushed_ = true;
    {
      std::lock_guard<std::mutex> lock(mu_);
      ++counters_.idle_flushes;
    }
    spdlog::warn("no input for {} s: releasing pending frames and finishing open windows",
                 config_.sync.idle_flush_s);
    EndOfInput();
  }
}

void Service::EndOfInput() {
  if (stopped_) return;
  std::vector<SyncAction> actions = sync_.Flush();
  flushing_.store(true, std::memory_order_release);
  Apply(&actions);
  FlushPipeline();
  const SyncStatus status = sync_.Status();
  std::lock_guard<std::mutex> lock(mu_);
  counters_.sync = status;
}

bool Service::Reload(const DaemonConfig& next, std::string* why) {
  std::string notes;
  for (const std::string& key : RestartOnlyChanges(config_, next)) {
    notes += (notes.empty() ? "" : ", ") + key;
  }
  if (!notes.empty()) notes = "changes to " + notes + " need a restart and were not applied";
  const bool tracker_changed =
      config::TrackerOptionsToYaml(next.tracker) != config::TrackerOptionsToYaml(config_.tracker);
  if (tracker_changed) {
    std::string reason;
    std::unique_ptr<pipeline::Pipeline> fresh = MakePipeline(next.tracker, &reason);
    if (!fresh) {
      if (why != nullptr) *why = "tracker options: " + reason;
      return false;
    }
    // End the current stream on the old pipeline, then switch.
    std::vector<SyncAction> actions = sync_.Flush();
    flushing_.store(true, std::memory_order_release);
    Apply(&actions);
    FlushPipeline();
    pipeline_->Stop();
    const pipeline::PipelineStatus old = pipeline_->Status();
    {
      std::lock_guard<std::mutex> lock(mu_);
      windows_before_ += old.tracker.windows_processed;
      jobs_failed_before_ += old.windows_failed;
      embeddings_used_before_ += old.tracker.embeddings_used;
      embeddings_dropped_before_ += old.tracker.embeddings_dropped;
      tracks_revived_before_ += old.tracker.tracks_revived;
      for (std::size_t i = 0; i < inputs_.size() && i < old.cameras.size(); ++i) {
        inputs_[i].rejected_before += old.cameras[i].detections_rejected;
        inputs_[i].embeddings_dropped_before += old.cameras[i].embeddings_dropped;
      }
      id_offset_ = max_published_id_;
    }
    pipeline_ = std::move(fresh);
    config_.tracker = next.tracker;
    output_layout_ = config_.tracker.mode == tracker::InputMode::kPoses
                         ? config_.tracker.layout
                         : core::KeypointLayoutId::kNone;
  }
  config_.log_level = next.log_level;
  config_.log_repeat_interval_s = next.log_repeat_interval_s;
  config_.status_period_s = next.status_period_s;
  config_.latency_limit_us = next.latency_limit_us;
  limiter_.SetInterval(Seconds(config_.log_repeat_interval_s));
  next_status_us_ = std::min(next_status_us_, Now() + Seconds(config_.status_period_s));
  config_hash_ = DaemonConfigHash(config_);
  {
    std::lock_guard<std::mutex> lock(mu_);
    ++counters_.reloads;
  }
  if (why != nullptr) *why = notes;
  return true;
}

void Service::Stop() {
  if (stopped_) return;
  EndOfInput();
  stopped_ = true;
  pipeline_->Stop();
  const std::vector<std::uint8_t> status = BuildStatus();
  Publish(config_.status_channel, status, Now());
  {
    std::lock_guard<std::mutex> lock(mu_);
    ++counters_.status_published;
  }
  if (analytics_) {
    std::lock_guard<std::mutex> analytics_lock(analytics_mu_);
    PublishSiteCounts(Now());
  }
  std::lock_guard<std::mutex> lock(out_mu_);
  if (record_) {
    std::string why;
    if (!record_->Flush(&why)) {
      spdlog::error("record log: {}", why);
      std::lock_guard<std::mutex> count_lock(mu_);
      ++counters_.record_errors;
    }
  }
}

std::int64_t Service::KernelDrops() const {
  if (!hooks_.kernel_drops) return -1;
  const std::optional<std::int64_t> now = hooks_.kernel_drops();
  std::int64_t seen = kernel_drops_.load(std::memory_order_relaxed);
  while (now && *now > seen &&
         !kernel_drops_.compare_exchange_weak(seen, *now, std::memory_order_relaxed)) {
  }
  return kernel_drops_.load(std::memory_order_relaxed);
}

ServiceCounters Service::Counters() const {
  const pipeline::PipelineStatus ps = pipeline_->Status();
  const std::int64_t kernel_drops = KernelDrops();
  std::lock_guard<std::mutex> lock(mu_);
  ServiceCounters c = counters_;
  c.kernel_drops = kernel_drops;
  c.pipeline = ps;
  c.log_suppressed = limiter_.suppressed_total();
  return c;
}

std::vector<std::uint8_t> Service::BuildStatus() {
  const std::int64_t now = Now();
  const pipeline::PipelineStatus ps = pipeline_->Status();
  std::vector<std::int64_t> window_latencies = pipeline_->TakeWindowLatencies();
  const SyncStatus ss = sync_.Status();
  const std::int64_t kernel_drops = KernelDrops();
  mvtrack::tracker_status_t msg;
  std::vector<std::int64_t> samples;
  {
    std::lock_guard<std::mutex> lock(mu_);
    samples.swap(latency_samples_);
    msg.utime = now;
    msg.period_us = now - period_start_us_;
    msg.uptime_us = now - start_us_;
    msg.instance_id = instance_id_;
    msg.start_utime = start_us_;
    msg.sequence = status_sequence_++;
    msg.version = hooks_.version;
    msg.config_hash = config_hash_;
    msg.last_frame = last_frame_;
    msg.active_tracks = active_tracks_;
    msg.confirmed_tracks = confirmed_tracks_;
    msg.windows_processed = windows_before_ + ps.tracker.windows_processed;
    msg.jobs_failed = jobs_failed_before_ + ps.windows_failed;
    const double period_s = std::max<double>(1.0, static_cast<double>(msg.period_us)) / 1e6;
    std::int64_t flags = 0;
    for (std::size_t i = 0; i < inputs_.size(); ++i) {
      CameraInput& in = inputs_[i];
      const SyncCameraStatus& sc = ss.cameras[i];
      mvtrack::camera_status_t cs;
      cs.camera_id = config_.cameras[i].id;
      cs.rate_hz = static_cast<float>(
          static_cast<double>(in.received - in.received_at_period_start) / period_s);
      cs.last_utime = in.last_utime;
      cs.last_receive_utime = in.last_receive_us;
      cs.received = in.received;
      cs.late = sc.late;
      cs.dropped = sc.flood + (i < ps.cameras.size() ? ps.cameras[i].frames_dropped : 0);
      cs.rejected = sc.detections_rejected + in.rejected_before +
                    (i < ps.cameras.size() ? ps.cameras[i].detections_rejected : 0);
      cs.embeddings_dropped = in.embeddings_dropped_before +
                              (i < ps.cameras.size() ? ps.cameras[i].embeddings_dropped : 0);
      cs.decode_errors = in.decode_errors;
      cs.lost = sc.lost;
      cs.clock_offset_us = sc.offset_us;
      cs.queue_depth = static_cast<std::int32_t>(
          i < ps.cameras.size() ? std::min<std::size_t>(ps.cameras[i].queue_depth, INT32_MAX) : 0);
      cs.queue_capacity = config_.camera_queue_capacity;
      std::int64_t f = 0;
      if (in.received == 0) f |= mvtrack::camera_status_t::FLAG_NO_DATA;
      // Silent by the synchronizer's rule (capture time), or nothing received for as long on the
      // wall clock: when every camera stops, capture time stops too and only the wall clock
      // tells (issue 39: a daemon whose cameras all went silent reported them delivering).
      const bool silent_now = now - in.last_receive_us > config_.sync.silent_after_us;
      if (in.received > 0 && (sc.excluded || silent_now)) {
        f |= mvtrack::camera_status_t::FLAG_STALE;
      }
      if (cs.late > in.late_at_period_start) f |= mvtrack::camera_status_t::FLAG_LATE;
      if (cs.dropped > in.dropped_at_period_start) f |= mvtrack::camera_status_t::FLAG_DROPPING;
      if (cs.rejected > in.rejected_at_period_start) f |= mvtrack::camera_status_t::FLAG_REJECTING;
      if (cs.decode_errors > in.decode_errors_at_period_start) {
        f |= mvtrack::camera_status_t::FLAG_DECODE_ERRORS;
      }
      if (sc.clock_flagged) f |= mvtrack::camera_status_t::FLAG_CLOCK_OFFSET;
      if (cs.lost > in.lost_at_period_start) f |= mvtrack::camera_status_t::FLAG_LOSING;
      if (cs.embeddings_dropped > in.embeddings_dropped_at_period_start) {
        f |= mvtrack::camera_status_t::FLAG_BAD_EMBEDDINGS;
      }
      cs.flags = f;
      if ((f & (mvtrack::camera_status_t::FLAG_NO_DATA | mvtrack::camera_status_t::FLAG_STALE)) !=
          0) {
        flags |= mvtrack::tracker_status_t::FLAG_CAMERA_MISSING;
      }
      if ((f & (mvtrack::camera_status_t::FLAG_LATE | mvtrack::camera_status_t::FLAG_DROPPING |
                mvtrack::camera_status_t::FLAG_DECODE_ERRORS)) != 0) {
        flags |= mvtrack::tracker_status_t::FLAG_INPUT_LOSS;
      }
      in.received_at_period_start = in.received;
      in.late_at_period_start = cs.late;
      in.dropped_at_period_start = cs.dropped;
      in.rejected_at_period_start = cs.rejected;
      in.decode_errors_at_period_start = cs.decode_errors;
      in.lost_at_period_start = cs.lost;
      in.embeddings_dropped_at_period_start = cs.embeddings_dropped;
      msg.cameras.push_back(cs);
    }
    msg.num_cameras = static_cast<std::int16_t>(msg.cameras.size());
    msg.executor_queue_depth =
        static_cast<std::int32_t>(std::min<std::size_t>(ps.executor.queued, INT32_MAX));
    if (ps.executor.queue_capacity > 0 && ps.executor.queued >= ps.executor.queue_capacity) {
      flags |= mvtrack::tracker_status_t::FLAG_BACKLOG;
    }
    if (msg.jobs_failed > jobs_failed_at_period_start_) {
      flags |= mvtrack::tracker_status_t::FLAG_JOB_FAILURES;
    }
    jobs_failed_at_period_start_ = msg.jobs_failed;
    msg.kernel_drops = kernel_drops;
    msg.embeddings_used = embeddings_used_before_ + ps.tracker.embeddings_used;
    msg.embeddings_dropped = embeddings_dropped_before_ + ps.tracker.embeddings_dropped;
    msg.tracks_revived = tracks_revived_before_ + ps.tracker.tracks_revived;
    msg.gallery_bytes = ps.tracker.gallery_bytes;
    if (kernel_drops > kernel_drops_at_period_start_) {
      flags |= mvtrack::tracker_status_t::FLAG_INPUT_LOSS;
    }
    kernel_drops_at_period_start_ = std::max<std::int64_t>(0, kernel_drops);
    msg.num_latency_samples =
        static_cast<std::int32_t>(std::min<std::size_t>(samples.size(), INT32_MAX));
    msg.latency_max_us = samples.empty() ? 0 : *std::max_element(samples.begin(), samples.end());
    msg.latency_p50_us = NearestRankPercentile(&samples, 0.5);
    msg.latency_p99_us = NearestRankPercentile(&samples, 0.99);
    if (msg.latency_p99_us > config_.latency_limit_us) {
      flags |= mvtrack::tracker_status_t::FLAG_LATENCY_HIGH;
    }
    // Input keeps arriving, nothing is published: tracking stopped (every camera-frame
    // rejected, a stalled pipeline). Judged from the later of the last publish and the start of
    // the current run of input, so neither start-up nor a return from idle counts.
    const bool input_now = now - last_message_us_ < kNoOutputAfterUs;
    if (input_now && now - std::max(last_publish_us_, input_since_us_) >= kNoOutputAfterUs) {
      flags |= mvtrack::tracker_status_t::FLAG_NO_OUTPUT;
    }
    msg.flags = flags;
    period_start_us_ = now;
  }
  spdlog::debug(
      "status: {} frame(s) published, latency p50 {} us p99 {} us; window latency "
      "p50 {} us p99 {} us over {} window(s); flags {}",
      msg.num_latency_samples,
      msg.latency_p50_us,
      msg.latency_p99_us,
      NearestRankPercentile(&window_latencies, 0.5),
      NearestRankPercentile(&window_latencies, 0.99),
      window_latencies.size(),
      msg.flags);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  const int written = msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  if (written < 0) bytes.clear();
  return bytes;
}

}  // namespace mvtrack::service
