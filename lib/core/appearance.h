#pragma once
/// @file
/// Appearance (re-identification) embeddings as the tracker uses them (the paper's "w/
/// appearance" variant, DeepSORT-style): the options, the validation of untrusted embeddings
/// and the cosine distance. Stateless functions, pure data.

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace mvtrack::core {

/// How appearance embeddings are used. On by default, which changes nothing on a stream
/// without embeddings: with `enabled` false (or a stream without embeddings) the output is
/// exactly that of the same stream without embeddings (docs/DECISIONS.md "Appearance": on
/// measured better on the simulator's scenes with embeddings).
struct AppearanceOptions {
  /// Use the detections' embeddings (those that pass core::CheckEmbedding). false: they are
  /// ignored (not even validated).
  bool enabled = true;
  /// Window descriptors (the mean of a person's embeddings over one window) a long-term track
  /// keeps, newest first replacing the oldest: the gallery whose nearest entry is the track's
  /// appearance distance (DeepSORT's gallery, per window instead of per detection: one
  /// descriptor averages tens of detections). >= 1.
  int gallery_size = 16;
  /// A new tracklet takes the id of a track that left (or was lost) when its appearance distance
  /// to that track is at most this (cosine distance, 1 - cos; 0 identical, 1 orthogonal). In
  /// [0, 2].
  double reid_max_distance = 0.2;
  /// ... and the second-nearest candidate (on both sides: the track's other candidate
  /// tracklets, the tracklet's other candidate tracks) is farther by at least this: an ambiguous
  /// match starts a new id. In [0, 2].
  double reid_margin = 0.03;
  /// A rival within reid_margin does not make a re-identification ambiguous when it and the
  /// chosen track were never seen at the same time (one's last frame before the other's first)
  /// and their galleries are within reid_margin of each other: the person's earlier and later
  /// fragments (on the simulator's look-alike 0.5 scenes no twin was given the other's id so,
  /// docs/DECISIONS.md "Appearance"). false: only the evidence of
  /// linking::LinkedTrack::same_person counts.
  bool reid_disjoint_same_person = true;
  /// Tracks that ended are remembered for re-identification this long, seconds of stream time
  /// since their last frame. Finite, >= 0.
  double max_reid_s = 120.0;
  /// A tracklet that would be born tentative (window linking: fewer than strong_birth_cameras
  /// cameras, next to somebody else) is not re-identified at birth but when its track is linked
  /// again, on that window's evidence (it is not output before, so waiting costs no id): most
  /// such births are fragments or misplaced copies of a person that last one window.
  /// false: re-identified at birth.
  bool defer_weak_reid = true;
  /// At most this many ended tracks are remembered (the oldest is forgotten first): bounds the
  /// galleries' memory to max_departed x gallery_size x dimension floats. >= 0.
  int max_departed = 256;
  /// Window linking: a track never takes a tracklet (at any stage: overlap, gap, motion
  /// re-identification) whose descriptor is farther than this from its gallery: it looks
  /// like somebody else (an id passing from one person to another). In [0, 2]; 2 disables.
  double link_max_distance = 0.4;
  /// Cross-view association: a finite Eq. 4 distance between 2D tracklets of two cameras
  /// becomes d + association_weight x the cosine distance of their mean embeddings
  /// (association::AssociationOptions::appearance_weight; ∅ and ∞ unchanged). Finite, >= 0.
  double association_weight = 0.3;
  /// Cross-view association: two cameras' 2D tracklets whose mean embeddings are farther apart
  /// than this cannot be one person (∞, PDNC's cannot-link), where each tracklet's embeddings
  /// agree well enough to tell (association::AssociationOptions::appearance_gate). In [0, 2];
  /// 2 disables.
  double association_gate = 0.5;
  /// SORT per camera (tracking2d::SortAppearance): weight of the appearance distance in the
  /// fused cost (1 - w) (1 - IoU) + w d. In [0, 1].
  double sort_weight = 0.3;
  /// SORT: a detection farther than this (cosine distance to the track's nearest gallery
  /// entry) never continues the track. In [0, 2].
  double sort_gate = 0.6;
  /// SORT: embeddings a 2D track keeps. >= 1.
  int sort_gallery_size = 32;

  /// Checks the ranges above; on failure writes a reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// What a camera's embeddings must agree with: fixed by its first valid embedding.
struct EmbeddingStream {
  std::size_t dimension = 0;  ///< 0: nothing seen yet
  std::string model;          ///< the model name of the first valid embedding (may be empty)
};

/// Longest embedding accepted (the wire format's decode limit).
inline constexpr std::size_t kMaxEmbeddingSize = 4096;

/// Validates `embedding` (untrusted, from `model`) against the camera's `stream` and normalises
/// it to unit length in place. Returns an empty string when it is usable; otherwise the reason
/// it is not (the caller drops the embedding and keeps the detection): empty, longer than
/// kMaxEmbeddingSize, a non-finite value, (near) zero length, or a dimension or model other than
/// the stream's. The first usable embedding of a stream fixes its dimension and model.
std::string CheckEmbedding(std::string_view model,
                           std::vector<float>* embedding,
                           EmbeddingStream* stream);

/// Shared, immutable embedding (one detection's; copied cheaply into every window it is in).
using EmbeddingPtr = std::shared_ptr<const std::vector<float>>;

/// The unit-length mean of embeddings: Add() each (those of another length than the first are
/// skipped), then Unit(). Accumulates in double.
class EmbeddingMean {
 public:
  void Add(const std::vector<float>& embedding);
  /// Embeddings added (of the first one's length).
  int count() const { return count_; }
  /// The mean direction, unit length; empty when nothing was added or the sum is (near) zero.
  std::vector<float> Unit() const;
  /// |sum|: count() when every embedding added was the same, about sqrt(count()) when they are
  /// unrelated.
  double Length() const;

 private:
  std::vector<double> sum_;
  int count_ = 0;
};

/// Cosine distance 1 - a.b of two unit vectors of the same length (checked), in [0, 2].
double CosineDistance(const std::vector<float>& a, const std::vector<float>& b);

/// The nearest entry of `gallery` to `query` (CosineDistance); entries of another length are
/// skipped. 2 (the largest distance) when none is comparable.
double GalleryDistance(const std::vector<std::vector<float>>& gallery,
                       const std::vector<float>& query);

}  // namespace mvtrack::core
