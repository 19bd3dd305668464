#include "viz/image_io.h"

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
  auto writer = std::make_unique<cv::VideoWriter>();
  try {
    writer->open(path, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), fps, frame_size, true);
  } catch (const cv::Exception& e) {
    return fail(std::string("cannot open an MP4 writer: ") + e.what());
  }
  if (!writer->isOpened()) {
    return fail(
        "cannot open an MP4 writer (no MPEG-4 encoder in this OpenCV videoio build, or "
        "the file cannot be created)");
  }
  return std::unique_ptr<VideoFileWriter>(new VideoFileWriter(std::move(writer), frame_size));
}

VideoFileWriter::VideoFileWriter(std::unique_ptr<cv::VideoWriter> writer, cv::Size size)
    : writer_(std::move(writer)), size_(size) {}

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
