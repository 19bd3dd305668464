#pragma once
/// @file
/// A set of calibrated cameras with precomputed projection and fundamental matrices for every
/// ordered pair, and (once ComputeSharedViews ran, which its owner does before sharing it) which
/// pairs can see one place. Thread-compatible: const methods only once shared.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "geometry/camera_model.h"

namespace mvtrack::geometry {

class CameraRig {
 public:
  CameraRig() = default;
  /// Cameras must have distinct ids and pass Validate(); otherwise `why` is set and the rig is
  /// empty (check `ok()`).
  explicit CameraRig(std::vector<CameraModel> cameras, std::string* why = nullptr);

  bool ok() const { return !cameras_.empty(); }
  int size() const { return static_cast<int>(cameras_.size()); }
  const std::vector<CameraModel>& cameras() const { return cameras_; }

  /// Dense index (0..size-1, in ascending id order) of camera `id`, or nullopt if unknown.
  std::optional<int> IndexOf(CameraId id) const;
  const CameraModel& camera(int index) const { return cameras_[static_cast<std::size_t>(index)]; }
  const Mat34& projection(int index) const { return projections_[static_cast<std::size_t>(index)]; }
  /// Whether cameras `a` and `b` (indices) can see one place (ComputeSharedViews); true for
  /// every pair until it was computed, and for a == b.
  bool SharesView(int a, int b) const {
    return shares_view_.empty() ||
           shares_view_[static_cast<std::size_t>(a) * static_cast<std::size_t>(size()) +
                        static_cast<std::size_t>(b)] != 0;
  }
  /// Marks the pairs of cameras that can see one place of a person standing on the floor
  /// z = `floor_z`: their views (ViewOnPlane, `max_range_m` along each optical axis) of one of
  /// the planes floor_z - 0.5, floor_z, ..., floor_z + 2.5 m share at least 0.25 m² (about
  /// one person's footprint). Conservative: a margin for lens distortion, a range far beyond
  /// where a person is still detected.
  void ComputeSharedViews(double floor_z, double max_range_m = kSharedViewRangeM);
  /// Pairs of cameras that share a view (each pair once; all of them before
  /// ComputeSharedViews).
  int num_sharing_pairs() const;

  /// ComputeSharedViews's default range along the optical axis, metres.
  static constexpr double kSharedViewRangeM = 60.0;

  /// F mapping undistorted points of camera index `from` to epipolar lines in camera `to`.
  const Mat3& fundamental(int from, int to) const {
    return fundamentals_[static_cast<std::size_t>(from) * static_cast<std::size_t>(size()) +
                         static_cast<std::size_t>(to)];
  }

 private:
  std::vector<CameraModel> cameras_;
  std::vector<Mat34> projections_;
  std::vector<Mat3> fundamentals_;
  std::map<CameraId, int> index_of_;
  std::vector<char> shares_view_;  // size() x size(); empty: not computed (every pair shares)
};

}  // namespace mvtrack::geometry
