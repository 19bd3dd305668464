#pragma once
/// @file
/// Internal to lib/datasets: reader of 4D Association's skeleton text format (Shelf's gt.txt
/// and skel.txt), whitespace-separated:
///   J F                         joints per skeleton, frames
///   per frame: N                people in the frame
///     per person: id, then 4 rows of J numbers (x, y, z in metres, then a confidence/valid row)
/// Stateless.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace mvtrack::datasets::internal {

/// One person of one frame: `rows` is 4 x J (x, y, z, confidence).
struct SkelTextPerson {
  std::int64_t id = 0;
  Eigen::Matrix<double, 4, Eigen::Dynamic> rows;
};

/// A parsed file.
struct SkelTextFile {
  int num_joints = 0;
  std::vector<std::vector<SkelTextPerson>> frames;
};

/// Reads `file`. `expected_joints` > 0 requires that joint count.
/// @throws DatasetError (file, line and what was expected) on any malformed content: missing
///   or non-numeric tokens, negative counts, ids out of range, duplicate ids in a frame,
///   non-finite values, trailing tokens.
SkelTextFile ReadSkelText(const std::filesystem::path& file, int expected_joints);

}  // namespace mvtrack::datasets::internal
