#pragma once
/// @file
/// The Shelf dataset (Belagiannis et al., "3D Pictorial Structures for Multiple Human Pose
/// Estimation", CVPR 2014) as released by 4D Association (Zhang et al., CVPR 2020): 5 cameras,
/// 301 frames (the standard test range 300-600), real OpenPose BODY25 detections, 3D ground
/// truth of 4 actors, and 4D Association's own tracking output. Files and formats:
/// `<data_root>/shelf/SOURCE.md`. Stateless functions.

#include <filesystem>
#include <string>

#include "datasets/dataset.h"

namespace mvtrack::datasets {

/// Options of LoadShelf.
struct ShelfOptions {
  /// Frame rate used for CameraFrame::utime. The source does not state Shelf's frame rate; 25
  /// fps is assumed (the rate of Campus, recorded by the same group with the same kind of
  /// cameras). Only timestamps depend on it.
  double fps = 25.0;

  /// fps finite and > 0. On failure writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// Loads Shelf from `data_root`/shelf:
///  - cameras: 4d_association/calibration.json (K, RT world->camera in metres, z up,
///    1032x776, no distortion), camera ids 0..4;
///  - frames: line i of the 4D Association files is Shelf frame 300 + i (the standard test
///    range 300-600, 301 frames; the repository does not state the offset, see SOURCE.md);
///  - detections: derived/persons2d_body25_cam{0..4}.json, the real OpenPose BODY25
///    candidates assembled into people with 4D Association's greedy PAF rule; each person is
///    one Detection2D in layout kBody25 (score-0 keypoints are not detected), box =
///    BoxFromKeypoints, score = MeanKeypointScore; source ids are kUnknownSourceId;
///  - ground truth: 4d_association/gt.txt, 15 joints of which the 15th (pelvis) is dropped,
///    giving kShelf14; actor ids 0..3 (the usual PCP protocol scores ids 0, 1, 2).
/// @throws DatasetError on a missing or malformed file, or when the files disagree (camera
///   count, frame count, image size).
Dataset LoadShelf(const std::filesystem::path& data_root, const ShelfOptions& options = {});

/// 4D Association's own tracking output on Shelf (4d_association/skel.txt: SKEL19 skeletons,
/// metres, ids 0..4), for side-by-side scoring. SKEL19 joint order (4D Association's
/// `GetSkelMapping(BODY25, SKEL19)`): 0 mid_hip, 1 neck, 2 r_hip, 3 l_hip, 4 nose,
/// 5 r_shoulder, 6 l_shoulder, 7 r_knee, 8 l_knee, 9 r_ear, 10 l_ear, 11 r_elbow, 12 l_elbow,
/// 13 r_ankle, 14 l_ankle, 15 r_wrist, 16 l_wrist, 17 l_big_toe, 18 r_big_toe. A joint is
/// present when its 4th row (confidence) is > 0; people without any present joint are
/// left out. The shelf14 mapping is the one of 4D Association's evaluation (`MappingToShelf`,
/// evaluate_shelf): limbs copied, and
///   head_bottom = shoulder_mid + 0.5 (ear_mid - shoulder_mid),
///   head_top    = head_bottom + 0.125 m * face + 0.145 m * z,
///   face        = normalize((neck - mid_hip) x (r_shoulder - l_shoulder)),
/// a derived joint being present only when all its inputs are. Frames are Shelf frames
/// 300 + i as for LoadShelf.
/// `which` picks the run: 4D Association's default `windows` branch (4d_association/skel.txt)
/// or its older `linux` branch run here on the same detections (4d_association_linux/skel.txt,
/// SOURCE.md); both are in the same format.
/// @throws DatasetError on a missing or malformed file.
enum class Shelf4DARun {
  kWindows,  ///< 4d_association/skel.txt ("4d_association")
  kLinux,    ///< 4d_association_linux/skel.txt ("4d_association_linux")
};
PeerOutput LoadShelfPeer4DA(const std::filesystem::path& data_root,
                            Shelf4DARun which = Shelf4DARun::kWindows);

}  // namespace mvtrack::datasets
