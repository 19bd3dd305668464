#include "pipeline/camera_queue.h"

#include <utility>
#include <vector>

#include "core/check.h"

namespace mvtrack::pipeline {

const char* ToString(OverflowPolicy policy) {
  switch (policy) {
    case OverflowPolicy::kDropOldest:
      return "drop_oldest";
    case OverflowPolicy::kBlock:
      return "block";
  }
  return "?";
}

void WorkSignal::Notify() {
  bool wake = false;
  {
    std::lock_guard<std::mutex> lock(mu_);
    pending_ = true;
    wake = waiting_;
  }
  if (wake) cv_.notify_one();
}

void WorkSignal::Wait() {
  std::unique_lock<std::mutex> lock(mu_);
  waiting_ = true;
  cv_.wait(lock, [&] { return pending_; });
  waiting_ = false;
  pending_ = false;
}

CameraQueue::CameraQueue(int capacity, OverflowPolicy policy, WorkSignal* signal)
    : capacity_(capacity), policy_(policy), signal_(signal) {
  MVTRACK_CHECK_MSG(capacity >= 1, "CameraQueue capacity must be >= 1");
}

bool CameraQueue::Push(CameraWork work) {
  MVTRACK_CHECK(!work.dropped);
  {
    std::unique_lock<std::mutex> lock(mu_);
    const auto full = [&] {
      return items_.size() - dropped_prefix_ >= static_cast<std::size_t>(capacity_);
    };
    if (policy_ == OverflowPolicy::kBlock) {
      space_cv_.wait(lock, [&] { return closed_ || !full(); });
    }
    if (closed_) return false;
    if (full()) {
      // kDropOldest: the oldest item that still has detections loses them.
      CameraWork& oldest = items_[dropped_prefix_];
      std::vector<core::Detection2D>().swap(oldest.frame.detections);
      oldest.dropped = true;
      ++dropped_prefix_;
      ++dropped_total_;
    }
    items_.push_back(std::move(work));
  }
  item_cv_.notify_one();
  if (signal_ != nullptr) signal_->Notify();
  return true;
}

bool CameraQueue::TakeFront(std::optional<CameraWork>* out) {
  *out = std::move(items_.front());
  items_.pop_front();
  if (dropped_prefix_ > 0) {
    MVTRACK_DCHECK((*out)->dropped);
    --dropped_prefix_;
    return false;  // a dropped header frees no room for detections
  }
  return true;
}

std::optional<std::uint64_t> CameraQueue::FrontSeq() const {
  std::lock_guard<std::mutex> lock(mu_);
  if (items_.empty()) return std::nullopt;
  return items_.front().seq;
}

std::optional<CameraWork> CameraQueue::TryPop() {
  std::optional<CameraWork> out;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (items_.empty() || !TakeFront(&out)) return out;
  }
  space_cv_.notify_one();
  return out;
}

bool CameraQueue::Finished() const {
  std::lock_guard<std::mutex> lock(mu_);
  return closed_ && items_.empty();
}

std::optional<CameraWork> CameraQueue::Pop() {
  std::optional<CameraWork> out;
  {
    std::unique_lock<std::mutex> lock(mu_);
    item_cv_.wait(lock, [&] { return closed_ || !items_.empty(); });
    if (items_.empty()) return std::nullopt;
    if (!TakeFront(&out)) return out;
  }
  space_cv_.notify_one();
  return out;
}

void CameraQueue::Close() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    closed_ = true;
  }
  item_cv_.notify_all();
  space_cv_.notify_all();
  if (signal_ != nullptr) signal_->Notify();
}

std::size_t CameraQueue::depth() const {
  std::lock_guard<std::mutex> lock(mu_);
  return items_.size() - dropped_prefix_;
}

std::int64_t CameraQueue::dropped() const {
  std::lock_guard<std::mutex> lock(mu_);
  return dropped_total_;
}

}  // namespace mvtrack::pipeline
