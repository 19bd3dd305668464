#pragma once
/// @file
/// How a provisional layer agrees with the final output of the same run (tracker::
/// ProvisionalEstimator): per provisional track-frame, whether the final output has that id at
/// that frame, and how far apart the two footprints are. Stateless, pure.

#include <cstdint>

#include "eval/sequence.h"

namespace mvtrack::eval {

/// The agreement of a provisional layer with the final output.
struct LayerAgreement {
  std::int64_t provisional_track_frames = 0;  ///< (frame, id) of the provisional layer
  std::int64_t final_track_frames = 0;        ///< (frame, id) of the final output
  /// Provisional track-frames whose id the final output has at that frame.
  std::int64_t same_id = 0;
  /// Final track-frames the provisional layer has under the same id.
  std::int64_t final_covered = 0;
  /// Over the same-id track-frames: footprint distance (x, y), metres; NaN without any.
  double median_distance_m = 0.0;
  double p90_distance_m = 0.0;
  double max_distance_m = 0.0;

  /// same_id / provisional_track_frames (1 without provisional track-frames).
  double same_id_fraction() const;
  /// final_covered / final_track_frames (1 without final track-frames).
  double coverage() const;
};

/// Compares `provisional` with `final_output` frame by frame (frames matched by index; a frame
/// only on one side counts its track-frames there). Both must be valid sequences
/// (ValidateSequence; unchecked here).
LayerAgreement CompareLayers(const EvalSequence& final_output, const EvalSequence& provisional);

}  // namespace mvtrack::eval
