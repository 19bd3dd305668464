// Untrusted embeddings: validation against the camera's stream, normalisation, distances.

#include "core/appearance.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace mvtrack::core {
namespace {

TEST_CASE("CheckEmbedding normalises and fixes the stream's dimension and model", "[unit]") {
  EmbeddingStream stream;
  std::vector<float> e = {3.0f, 4.0f};
  CHECK(CheckEmbedding("osnet", &e, &stream).empty());
  CHECK(e[0] == Approx(0.6f));
  CHECK(e[1] == Approx(0.8f));
  CHECK(stream.dimension == 2u);
  CHECK(stream.model == "osnet");
  std::vector<float> longer = {1.0f, 0.0f, 0.0f};
  CHECK(CheckEmbedding("osnet", &longer, &stream).find("the camera's model gives 2") !=
        std::string::npos);
  std::vector<float> other_model = {1.0f, 0.0f};
  CHECK(CheckEmbedding("fastreid", &other_model, &stream).find("embedding_model") !=
        std::string::npos);
  std::vector<float> fine = {0.0f, -2.0f};
  CHECK(CheckEmbedding("osnet", &fine, &stream).empty());
  CHECK(fine[1] == -1.0f);
}

TEST_CASE("CheckEmbedding rejects what cannot be used, with a reason", "[unit]") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  struct Case {
    std::vector<float> e;
    const char* reason;
  };
  const Case cases[] = {
      {{}, "empty"},
      {{nan, 1.0f}, "non-finite"},
      {{1.0f, -inf}, "non-finite"},
      {{0.0f, 0.0f}, "zero length"},
      {{1e-9f, -1e-9f}, "zero length"},
      {std::vector<float>(kMaxEmbeddingSize + 1, 0.1f), "more than the limit"},
  };
  for (const Case& c : cases) {
    EmbeddingStream stream;
    std::vector<float> e = c.e;
    const std::string why = CheckEmbedding("m", &e, &stream);
    INFO(why);
    CHECK(why.find(c.reason) != std::string::npos);
    CHECK(stream.dimension == 0u);  // a bad embedding never fixes the stream
  }
}

TEST_CASE("cosine and gallery distances", "[unit]") {
  const std::vector<float> x = {1.0f, 0.0f}, y = {0.0f, 1.0f}, minus_x = {-1.0f, 0.0f};
  CHECK(CosineDistance(x, x) == 0.0);
  CHECK(CosineDistance(x, y) == Approx(1.0));
  CHECK(CosineDistance(x, minus_x) == Approx(2.0));
  CHECK(GalleryDistance({y, minus_x}, x) == Approx(1.0));
  CHECK(GalleryDistance({}, x) == 2.0);
  CHECK(GalleryDistance({{1.0f, 0.0f, 0.0f}}, x) == 2.0);  // other dimension: not comparable
}

TEST_CASE("AppearanceOptions::Validate names the bad field", "[unit]") {
  std::string why;
  CHECK(AppearanceOptions{}.Validate(&why));
  AppearanceOptions o;
  o.gallery_size = 0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("gallery_size") != std::string::npos);
  o = {};
  o.reid_max_distance = std::nan("");
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("reid_max_distance") != std::string::npos);
  o = {};
  o.reid_margin = 3.0;
  CHECK_FALSE(o.Validate(&why));
  o = {};
  o.max_reid_s = -1.0;
  CHECK_FALSE(o.Validate(&why));
  o = {};
  o.max_departed = -1;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("max_departed") != std::string::npos);
}

}  // namespace
}  // namespace mvtrack::core
