#include "viz/image_io.h"

#include <array>
#include <cmath>
#include <exception>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <vector>

#include "core/check.h"

namespace mvtrack::viz {

bool WriteImage(const std::string& path, const cv::Mat& image, std::string* why) {
  auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = path + ": " + reason;
    return false;
  };
  if (image.empty()) return fail("empty image");
  try {
    const std::vector<int> params = {cv::IMWRITE_PNG_COMPRESSION, 9};
    if (!cv::imwrite(path, image, params)) {
      return fail("cannot be written (directory missing, not writable, or unknown extension)");
    }
  } catch (const cv::Exception& e) {
    return fail(std::string("cannot be written: ") + e.what());
  }
  return true;
}

std::unique_ptr<VideoFileWriter> VideoFileWriter::Open(const std::string& path,
                                                       cv::Size frame_size,
                                                       double fps,
                                                       std::string* why) {
  auto fail = [&](const std::string& reason) -> std::unique_ptr<VideoFileWriter> {
    if (why != nullptr) *why = path + ": " + reason;
    return nullptr;
  };
  if (frame_size.width < 2 || frame_size.height < 2) return fail("frame size too small");
  if (!(fps > 0.0) || !std::isfinite(fps) || fps > 1000.0)
    return fail("frame rate must be in (0, 1000]");
  // H.264 first (browsers and most players play it); MPEG-4 Part 2 where the installed
  // OpenCV / FFmpeg has no H.264 encoder.
  struct Codec {
    int fourcc;
    const char* name;
  };
  const std::array<Codec, 2> kCodecs = {
      {{cv::VideoWriter::fourcc('a', 'v', 'c', '1'), "H.264 (avc1)"},
       {cv::VideoWriter::fourcc('m', 'p', '4', 'v'),
        "MPEG-4 Part 2 (mp4v): this OpenCV/FFmpeg build has no H.264 encoder, and browsers do "
        "not play mp4v (ffmpeg -i IN.mp4 -c:v libx264 OUT.mp4 converts it)"}}};
  std::string last_error;
  for (const Codec& codec : kCodecs) {
    auto writer = std::make_unique<cv::VideoWriter>();
    try {
      writer->open(path, codec.fourcc, fps, frame_size, true);
    } catch (const cv::Exception& e) {
      last_error = e.what();
      continue;
    }
    if (writer->isOpened()) {
      return std::unique_ptr<VideoFileWriter>(
          new VideoFileWriter(std::move(writer), frame_size, codec.name));
    }
  }
  return fail(
      "cannot open an MP4 writer (no H.264 or MPEG-4 encoder in this OpenCV videoio "
      "build, or the file cannot be created)" +
      (last_error.empty() ? std::string() : ": " + last_error));
}

VideoFileWriter::VideoFileWriter(std::unique_ptr<cv::VideoWriter> writer,
                                 cv::Size size,
                                 std::string codec)
    : writer_(std::move(writer)), size_(size), codec_(std::move(codec)) {}

VideoFileWriter::~VideoFileWriter() { Close(); }

void VideoFileWriter::Write(const cv::Mat& frame) {
  MVTRACK_CHECK(writer_ != nullptr);
  MVTRACK_CHECK(!frame.empty() && frame.type() == CV_8UC3);
  if (frame.size() == size_) {
    writer_->write(frame);
  } else {
    cv::Mat resized;
    cv::resize(frame, resized, size_, 0.0, 0.0, cv::INTER_AREA);
    writer_->write(resized);
  }
  ++frames_written_;
}

void VideoFileWriter::Close() {
  if (writer_) {
    writer_->release();
    writer_.reset();
  }
}

}  // namespace mvtrack::viz
