#include "tracker/tracker.h"

#include <utility>
#include <variant>

namespace mvtrack::tracker {

std::unique_ptr<Tracker> Tracker::Create(geometry::CameraRig rig,
                                         TrackerOptions options,
                                         std::string* why,
                                         bool provisional) {
  if (!options.Validate(why)) return nullptr;
  if (rig.size() < 2) {
    if (why != nullptr) {
      *why = "the camera rig has " + std::to_string(rig.size()) +
             " camera(s); at least 2 are needed to triangulate";
    }
    return nullptr;
  }
  return std::unique_ptr<Tracker>(new Tracker(std::move(rig), std::move(options), provisional));
}

Tracker::Tracker(geometry::CameraRig rig, TrackerOptions options, bool provisional)
    : rig_(WithSharedViews(std::move(rig), options)),
      options_(std::move(options)),
      num_points_(NumPoints(options_)),
      gate_(rig_, options_),
      builder_(rig_, options_, /*keep_frame_views=*/provisional),
      workspace_(options_.triangulation),
      finalizer_(rig_, options_) {
  if (provisional) provisional_.emplace(rig_, options_);
  cameras_.reserve(static_cast<std::size_t>(rig_.size()));
  for (int i = 0; i < rig_.size(); ++i) cameras_.emplace_back(rig_.camera(i), i, options_);
  gallery_memory_ = GalleryMemory(cameras_.size());
}

AddResult Tracker::Add(const core::CameraFrame& frame) {
  AddResult result;
  const FrameAdmission admission = gate_.Admit(frame);
  if (admission.rejection != FrameRejection::kNone) {
    result.rejection = admission.rejection;
    result.reason = admission.reason;
    ++stats_.camera_frames_rejected;
    ++stats_.rejections[admission.rejection];
    return result;
  }
  if (admission.events.reanchor) ++stats_.reanchors;
  ++stats_.camera_frames_accepted;

  CameraStageCounters counters;
  TrackedCameraFrame tracked = cameras_[static_cast<std::size_t>(admission.camera_index)].Process(
      frame, admission.stream_epoch, &counters);
  gallery_memory_.SetCamera(static_cast<std::size_t>(admission.camera_index),
                            counters.sort_gallery_bytes);
  stats_.gallery_bytes = gallery_memory_.total();
  outputs_.clear();
  builder_.Add(admission.events, std::move(tracked), &outputs_);
  RunOutputs(&outputs_, &result.finalized);
  outputs_.clear();  // releases the processed window jobs now; the capacity stays

  result.reason = std::move(counters.first_rejection_reason);
  result.detections_used = counters.detections_used;
  result.detections_rejected = counters.detections_rejected;
  result.detections_repaired = counters.detections_repaired;
  result.detections_filtered = counters.detections_filtered;
  stats_.detections_used += result.detections_used;
  stats_.detections_rejected += result.detections_rejected;
  stats_.detections_repaired += result.detections_repaired;
  stats_.detections_filtered += result.detections_filtered;
  result.embeddings_used = counters.embeddings_used;
  result.embeddings_dropped = counters.embeddings_dropped;
  stats_.embeddings_used += counters.embeddings_used;
  stats_.embeddings_dropped += counters.embeddings_dropped;
  if (result.reason.empty()) result.reason = std::move(counters.first_embedding_reason);
  return result;
}

std::vector<Frame3D> Tracker::Flush() {
  std::vector<Frame3D> out;
  gate_.Flush();
  std::vector<BuilderOutput> outputs;
  builder_.Flush(&outputs);
  RunOutputs(&outputs, &out);
  return out;
}

std::vector<Frame3D> Tracker::TakeProvisional() {
  std::vector<Frame3D> out;
  out.swap(provisional_frames_);
  return out;
}

void Tracker::RunOutputs(std::vector<BuilderOutput>* outputs, std::vector<Frame3D>* finalized) {
  for (BuilderOutput& output : *outputs) {
    if (const ClosedFrame* closed = std::get_if<ClosedFrame>(&output)) {
      finalizer_.AddClosedFrame(*closed);
      if (provisional_) {
        provisional_frames_.push_back(
            provisional_->Estimate(closed->frame, closed->utime, closed->views));
      }
    } else if (WindowJob* job = std::get_if<WindowJob>(&output)) {
      WindowResult result = ProcessWindowJob(rig_, options_, *job, &workspace_);
      linking::LinkResult link = finalizer_.Finalize(result, finalized);
      if (provisional_) provisional_->OnLinked(finalizer_.linker());
      stats_.windows_processed = finalizer_.counters().windows_processed;
      stats_.tracks_born = finalizer_.counters().tracks_born;
      stats_.tracks_revived = finalizer_.counters().tracks_revived;
      gallery_memory_.SetLinker(finalizer_.counters().gallery_bytes);
      stats_.gallery_bytes = gallery_memory_.total();
      WindowOutput w;
      w.window_id = job->window_id;
      w.begin = job->begin;
      w.end = job->end;
      w.tracklets = std::move(job->tracklets);
      w.clusters = std::move(result.clusters);
      w.persons = std::move(result.persons);
      w.link = std::move(link);
      last_window_ = std::move(w);
    } else {
      finalizer_.EndStream(finalized);
      if (provisional_) provisional_->EndStream();
    }
  }
  stats_.frames_finalized = finalizer_.counters().frames_finalized;
}

}  // namespace mvtrack::tracker
