#include "viz/image_io.h"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <string>

#include "viz/colors.h"
#include "viz/viz_test_util.h"

namespace mvtrack::viz {
namespace {

using testing::ColorDistance;
using testing::PixelAt;

// A fresh directory under the system temporary directory, removed by the destructor.
struct TempDir {
  TempDir() {
    path =
        std::filesystem::temp_directory_path() / ("mvtrack_viz_test_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::filesystem::path path;
};

TEST_CASE("WriteImage writes a PNG that reads back losslessly, failures are reported", "[unit]") {
  TempDir dir;
  cv::Mat image(40, 60, CV_8UC3, kBackground);
  image.at<cv::Vec3b>(10, 20) = cv::Vec3b(1, 2, 3);
  const std::string path = (dir.path / "a.png").string();
  std::string why;
  REQUIRE(WriteImage(path, image, &why));
  const cv::Mat back = cv::imread(path, cv::IMREAD_COLOR);
  REQUIRE(back.size() == image.size());
  CHECK(cv::norm(back, image, cv::NORM_INF) == 0.0);
  CHECK_FALSE(WriteImage((dir.path / "missing" / "a.png").string(), image, &why));
  CHECK(why.find("missing") != std::string::npos);
  CHECK_FALSE(WriteImage((dir.path / "a.unknownext").string(), image, &why));
}

TEST_CASE("An MP4 is written and reads back with the right frame count and size", "[unit]") {
  TempDir dir;
  const std::string path = (dir.path / "v.mp4").string();
  std::string why;
  std::unique_ptr<VideoFileWriter> video =
      VideoFileWriter::Open(path, cv::Size(320, 240), 10.0, &why);
  if (!video) {
    WARN("SKIPPED: this OpenCV cannot encode MP4 here: " << why);
    return;
  }
  constexpr int kFrames = 12;
  for (int i = 0; i < kFrames; ++i) {
    cv::Mat frame(240, 320, CV_8UC3, TrackColor(i));
    video->Write(i == 3 ? cv::Mat(120, 160, CV_8UC3, TrackColor(i)) : frame);  // resized
  }
  CHECK(video->frames_written() == kFrames);
  video->Close();
  cv::VideoCapture capture(path);
  if (!capture.isOpened()) {
    WARN("SKIPPED: this OpenCV cannot decode the MP4 it wrote (no decoder)");
    return;
  }
  int read = 0;
  cv::Mat frame;
  while (capture.read(frame)) {
    CHECK(frame.size() == cv::Size(320, 240));
    // Flat colours survive lossy coding closely.
    CHECK(ColorDistance(PixelAt(frame, cv::Point(160, 120)), TrackColor(read)) <= 12.0);
    ++read;
  }
  CHECK(read == kFrames);
}

TEST_CASE("VideoFileWriter rejects bad sizes and rates", "[unit]") {
  std::string why;
  CHECK(VideoFileWriter::Open("/tmp/never.mp4", cv::Size(1, 1), 10.0, &why) == nullptr);
  CHECK(why.find("size") != std::string::npos);
  CHECK(VideoFileWriter::Open("/tmp/never.mp4", cv::Size(64, 64), 0.0, &why) == nullptr);
  CHECK(why.find("rate") != std::string::npos);
}

}  // namespace
}  // namespace mvtrack::viz
