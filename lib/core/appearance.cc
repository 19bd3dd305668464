#include "core/appearance.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace mvtrack::core {

bool AppearanceOptions::Validate(std::string* why) const {
  auto fail = [&](const char* msg) {
    if (why != nullptr) *why = msg;
    return false;
  };
  if (gallery_size < 1) return fail("gallery_size must be >= 1");
  if (!std::isfinite(reid_max_distance) || reid_max_distance < 0.0 || reid_max_distance > 2.0) {
    return fail("reid_max_distance must be in [0, 2]");
  }
  if (!std::isfinite(reid_margin) || reid_margin < 0.0 || reid_margin > 2.0) {
    return fail("reid_margin must be in [0, 2]");
  }
  if (!std::isfinite(max_reid_s) || max_reid_s < 0.0) return fail("max_reid_s must be >= 0");
  if (max_departed < 0) return fail("max_departed must be >= 0");
  if (!std::isfinite(link_max_distance) || link_max_distance < 0.0 || link_max_distance > 2.0) {
    return fail("link_max_distance must be in [0, 2]");
  }
  if (!std::isfinite(association_weight) || association_weight < 0.0) {
    return fail("association_weight must be finite and >= 0");
  }
  if (!std::isfinite(association_gate) || association_gate < 0.0 || association_gate > 2.0) {
    return fail("association_gate must be in [0, 2]");
  }
  if (!std::isfinite(sort_weight) || sort_weight < 0.0 || sort_weight > 1.0) {
    return fail("sort_weight must be in [0, 1]");
  }
  if (!std::isfinite(sort_gate) || sort_gate < 0.0 || sort_gate > 2.0) {
    return fail("sort_gate must be in [0, 2]");
  }
  if (sort_gallery_size < 1) return fail("sort_gallery_size must be >= 1");
  return true;
}

std::string CheckEmbedding(std::string_view model,
                           std::vector<float>* embedding,
                           EmbeddingStream* stream) {
  MVTRACK_CHECK(embedding != nullptr && stream != nullptr);
  std::vector<float>& e = *embedding;
  if (e.empty()) return "empty embedding";
  if (e.size() > kMaxEmbeddingSize) {
    return "embedding of " + std::to_string(e.size()) + " values, more than the limit of " +
           std::to_string(kMaxEmbeddingSize);
  }
  double n2 = 0.0;
  for (const float v : e) {
    if (!std::isfinite(v)) return "embedding with a non-finite value";
    n2 += static_cast<double>(v) * static_cast<double>(v);
  }
  const double n = std::sqrt(n2);
  // Below this length the direction is noise (float32 rounding of a zero vector).
  if (!(n > 1e-6) || !std::isfinite(n)) return "embedding of (near) zero length";
  if (stream->dimension != 0 && e.size() != stream->dimension) {
    return "embedding of " + std::to_string(e.size()) + " values, the camera's model gives " +
           std::to_string(stream->dimension);
  }
  if (stream->dimension != 0 && model != stream->model) {
    return "embedding_model \"" + std::string(model) + "\", the camera's is \"" + stream->model +
           "\"";
  }
  if (stream->dimension == 0) {
    stream->dimension = e.size();
    stream->model = std::string(model);
  }
  for (float& v : e) v = static_cast<float>(static_cast<double>(v) / n);
  return std::string();
}

void EmbeddingMean::Add(const std::vector<float>& embedding) {
  if (embedding.empty()) return;
  if (sum_.empty()) sum_.assign(embedding.size(), 0.0);
  if (embedding.size() != sum_.size()) return;
  for (std::size_t k = 0; k < sum_.size(); ++k) sum_[k] += static_cast<double>(embedding[k]);
  ++count_;
}

double EmbeddingMean::Length() const {
  double n2 = 0.0;
  for (const double v : sum_) n2 += v * v;
  return std::sqrt(n2);
}

std::vector<float> EmbeddingMean::Unit() const {
  const double n = Length();
  if (!(n > 1e-9)) return {};  // nothing, or embeddings that cancel out: says nothing
  std::vector<float> unit(sum_.size());
  for (std::size_t k = 0; k < sum_.size(); ++k) unit[k] = static_cast<float>(sum_[k] / n);
  return unit;
}

double CosineDistance(const std::vector<float>& a, const std::vector<float>& b) {
  MVTRACK_CHECK(a.size() == b.size());
  // Single-precision dot product (vectorised by Eigen): unit vectors, so the sum stays <= 1
  // and float rounding (~1e-7 relative) is far below any gate.
  const auto n = static_cast<Eigen::Index>(a.size());
  const float dot = Eigen::Map<const Eigen::VectorXf>(a.data(), n)
                        .dot(Eigen::Map<const Eigen::VectorXf>(b.data(), n));
  return std::clamp(1.0 - static_cast<double>(dot), 0.0, 2.0);
}

double GalleryDistance(const std::vector<std::vector<float>>& gallery,
                       const std::vector<float>& query) {
  double best = 2.0;
  for (const std::vector<float>& g : gallery) {
    if (g.size() == query.size() && !g.empty()) best = std::min(best, CosineDistance(g, query));
  }
  return best;
}

}  // namespace mvtrack::core
