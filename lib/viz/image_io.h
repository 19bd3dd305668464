#pragma once
/// @file
/// Writing pictures: PNG files and MP4 videos (OpenCV imgcodecs and videoio). Runtime code (file
/// I/O). VideoFileWriter is a single-owner, single-threaded object.

#include <memory>
#include <opencv2/core.hpp>
#include <string>

namespace cv {
class VideoWriter;
}  // namespace cv

namespace mvtrack::viz {

/// Writes `image` (CV_8UC3) to `path` in the format of its extension (.png, .jpg, ...; PNG with
/// the highest compression). Returns false and sets `why` (when not null) on failure, naming
/// the path.
bool WriteImage(const std::string& path, const cv::Mat& image, std::string* why);

/// An MP4 (MPEG-4 part 2, fourcc "mp4v") video file of fixed frame size.
class VideoFileWriter {
 public:
  /// Creates `path`, H.264 when the installed OpenCV/FFmpeg can encode it, else MPEG-4 Part 2
  /// (codec() says which, and why). Returns nullptr and sets `why` (when not null) when the
  /// frame size or rate is invalid or OpenCV cannot encode MP4 here (videoio built without
  /// FFmpeg/GStreamer).
  static std::unique_ptr<VideoFileWriter> Open(const std::string& path,
                                               cv::Size frame_size,
                                               double fps,
                                               std::string* why);
  /// Finishes the file (Close()).
  ~VideoFileWriter();
  VideoFileWriter(const VideoFileWriter&) = delete;
  VideoFileWriter& operator=(const VideoFileWriter&) = delete;

  /// Appends a frame; a frame of another size is resized (INTER_AREA) to the video's size.
  /// `frame` must be CV_8UC3 (checked).
  void Write(const cv::Mat& frame);
  /// Finishes the file; later Write calls abort (programmer error).
  void Close();
  /// Frames written.
  int frames_written() const { return frames_written_; }
  /// The codec written, in words (with the reason when it is not H.264).
  const std::string& codec() const { return codec_; }

 private:
  VideoFileWriter(std::unique_ptr<cv::VideoWriter> writer, cv::Size size, std::string codec);
  std::unique_ptr<cv::VideoWriter> writer_;
  cv::Size size_;
  std::string codec_;
  int frames_written_ = 0;
};

}  // namespace mvtrack::viz
