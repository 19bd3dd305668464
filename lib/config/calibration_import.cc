#include "config/calibration_import.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <set>
#include <string_view>
#include <system_error>
#include <utility>

#include "config/internal/yaml_node.h"
#include "datasets/calibration_files.h"
#include "datasets/dataset.h"
#include "json/json.h"

namespace mvtrack::config {
namespace {

using internal::kMaxImageSidePx;
// Largest difference allowed between a FileStorage Rot_<c> and Rodrigues(R_<c>).
constexpr double kRotationAgreement = 1e-6;
constexpr double kMmToM = 1e-3;
constexpr double kCmToM = 1e-2;
// WILDTRACK's cameras C1..C7 (the official file names) and its image size.
const std::vector<std::string> kWildtrackNames = {
    "CVLab1", "CVLab2", "CVLab3", "CVLab4", "IDIAP1", "IDIAP2", "IDIAP3"};
constexpr ImageSize kWildtrackImageSize{1920, 1080};
constexpr ImageSize kCampusImageSize{360, 288};

[[noreturn]] void Fail(const std::string& file, const std::string& key, const std::string& reason) {
  throw ConfigError(file, 0, 0, key, reason);
}

// Rotations printed with few decimals (VoxelPose: 6) are not orthonormal to CameraModel's 1e-6;
// within this distance of orthonormal they are replaced by the nearest rotation.
constexpr double kMaxRotationRounding = 1e-4;

// The nearest rotation (Frobenius norm: U Vᵀ of the SVD) of `m` when max|mᵀm - I| is at most
// kMaxRotationRounding and det(m) > 0; `m` itself otherwise (validation then reports it).
// `*changed` tells whether it was replaced.
Mat3 NearestRotation(const Mat3& m, bool* changed) {
  *changed = false;
  const double error = (m.transpose() * m - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (error == 0.0 || error > kMaxRotationRounding || !(m.determinant() > 0.0)) return m;
  const Eigen::JacobiSVD<Mat3> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  *changed = true;
  return svd.matrixU() * svd.matrixV().transpose();
}

// Validates a finished camera; the error names the file and the camera.
void ValidateCamera(const geometry::CameraModel& camera,
                    const std::string& file,
                    const std::string& what) {
  std::string why;
  if (!camera.Validate(&why)) Fail(file, what, why);
}

ImportedCalibration FromDataset(const std::vector<geometry::CameraModel>& cameras) {
  ImportedCalibration out;
  out.document.cameras = cameras;
  return out;
}

// Runs a lib/datasets parser, turning its DatasetError into a ConfigError.
template <typename F>
auto RunDatasetParser(F&& parse) -> decltype(parse()) {
  try {
    return parse();
  } catch (const datasets::DatasetError& e) {
    throw ConfigError(e.file(), 0, 0, "", e.problem());
  }
}

// ---- OpenCV FileStorage ------------------------------------------------------------------------

// An open FileStorage document and its path, with checked readers.
class Storage {
 public:
  explicit Storage(std::string path) : path_(std::move(path)) {
    std::error_code ec;
    if (!std::filesystem::exists(path_, ec)) Fail(path_, "", "file does not exist");
    if (!std::filesystem::is_regular_file(path_, ec)) Fail(path_, "", "not a regular file");
    try {
      if (!fs_.open(path_, cv::FileStorage::READ)) {
        Fail(path_, "", "cannot be opened as an OpenCV FileStorage (YAML or XML) file");
      }
    } catch (const cv::Exception& e) {
      Fail(path_, "", "not a valid OpenCV FileStorage file: " + std::string(e.what()));
    }
  }

  const std::string& path() const { return path_; }

  bool Has(const std::string& key) const {
    try {
      const cv::FileNode node = fs_[key];
      return !node.empty() && !node.isNone();
    } catch (const cv::Exception&) {
      return false;
    }
  }

  // A matrix node (!!opencv-matrix / type_id="opencv-matrix") or a sequence of numbers, as
  // doubles in row-major order, with its shape; a plain sequence is a column.
  std::vector<double> Matrix(const std::string& key, int* rows, int* cols) const {
    if (!Has(key)) Fail(path_, key, "missing entry");
    const cv::FileNode node = fs_[key];
    cv::Mat m;
    try {
      if (node.isSeq()) {
        std::vector<double> v;
        node >> v;
        m = cv::Mat(static_cast<int>(v.size()), 1, CV_64F);
        for (std::size_t i = 0; i < v.size(); ++i) m.at<double>(static_cast<int>(i), 0) = v[i];
      } else {
        node >> m;
      }
    } catch (const cv::Exception& e) {
      Fail(path_, key, "not a matrix: " + std::string(e.what()));
    }
    if (m.empty()) Fail(path_, key, "not a matrix (expected !!opencv-matrix or a list of numbers)");
    if (m.channels() != 1) Fail(path_, key, "a matrix with several channels");
    cv::Mat d;
    m.convertTo(d, CV_64F);
    std::vector<double> values;
    for (int r = 0; r < d.rows; ++r) {
      for (int c = 0; c < d.cols; ++c) {
        const double v = d.at<double>(r, c);
        if (!std::isfinite(v)) Fail(path_, key, "a value is not finite");
        values.push_back(v);
      }
    }
    *rows = d.rows;
    *cols = d.cols;
    return values;
  }

  // Exactly rows x cols.
  std::vector<double> Matrix(const std::string& key, int rows, int cols) const {
    int r = 0;
    int c = 0;
    std::vector<double> v = Matrix(key, &r, &c);
    if (r != rows || c != cols) {
      Fail(path_,
           key,
           "expected a " + std::to_string(rows) + "x" + std::to_string(cols) + " matrix, got " +
               std::to_string(r) + "x" + std::to_string(c));
    }
    return v;
  }

  // A vector: a 1xn or nx1 matrix with n in `sizes`.
  std::vector<double> Vector(const std::string& key, const std::vector<int>& sizes) const {
    int r = 0;
    int c = 0;
    std::vector<double> v = Matrix(key, &r, &c);
    const int n = static_cast<int>(v.size());
    const bool ok = (r == 1 || c == 1) && std::find(sizes.begin(), sizes.end(), n) != sizes.end();
    if (!ok) {
      std::string expected;
      for (int s : sizes) expected += (expected.empty() ? "" : " or ") + std::to_string(s);
      Fail(path_,
           key,
           "expected a vector of " + expected + " values, got a " + std::to_string(r) + "x" +
               std::to_string(c) + " matrix");
    }
    return v;
  }

  // A positive integer scalar.
  int PositiveInt(const std::string& key) const {
    const cv::FileNode node = fs_[key];
    if (!node.isInt() && !node.isReal()) Fail(path_, key, "expected an integer");
    const double v = node.real();
    if (!(v >= 1.0 && v <= kMaxImageSidePx) || v != std::floor(v)) {
      Fail(path_, key, "expected an integer in [1, " + std::to_string(kMaxImageSidePx) + "]");
    }
    return static_cast<int>(v);
  }

  // A sequence of names (strings; integers are accepted and written in decimal).
  std::vector<std::string> Names(const std::string& key) const {
    if (!Has(key)) Fail(path_, key, "missing entry (the list of camera names)");
    const cv::FileNode node = fs_[key];
    if (!node.isSeq()) Fail(path_, key, "expected a list of camera names");
    std::vector<std::string> names;
    for (auto it = node.begin(); it != node.end(); ++it) {
      const cv::FileNode item = *it;
      std::string name;
      if (item.isString()) {
        name = item.string();
      } else if (item.isInt()) {
        name = std::to_string(static_cast<int>(item));
      } else {
        Fail(path_, key + "[" + std::to_string(names.size()) + "]", "expected a camera name");
      }
      if (name.empty()) Fail(path_, key + "[" + std::to_string(names.size()) + "]", "empty name");
      names.push_back(name);
    }
    if (names.empty()) Fail(path_, key, "no cameras");
    return names;
  }

 private:
  std::string path_;
  cv::FileStorage fs_;
};

Mat3 ToMat3(const std::vector<double>& v) {
  Mat3 m;
  for (Eigen::Index r = 0; r < 3; ++r) {
    for (Eigen::Index c = 0; c < 3; ++c) m(r, c) = v[static_cast<std::size_t>(3 * r + c)];
  }
  return m;
}

geometry::Distortion ToDistortion(const std::vector<double>& d,
                                  const std::string& file,
                                  const std::string& key) {
  geometry::Distortion out;
  out.k1 = d[0];
  out.k2 = d[1];
  out.p1 = d[2];
  out.p2 = d[3];
  if (d.size() >= 5) out.k3 = d[4];
  for (std::size_t i = 5; i < d.size(); ++i) {
    if (d[i] != 0.0) {
      Fail(file,
           key,
           "k4..k6 (the rational distortion model) are not supported; only k1 k2 p1 "
           "p2 k3");
    }
  }
  return out;
}

// The ids of EasyMocap names: decimal values when all names are decimal and distinct, else
// positions.
std::vector<CameraId> IdsFromNames(const std::vector<std::string>& names, bool* numeric) {
  std::vector<CameraId> ids;
  std::set<CameraId> seen;
  for (const std::string& name : names) {
    CameraId id = 0;
    const char* end = name.data() + name.size();
    const auto [ptr, ec] = std::from_chars(name.data(), end, id);
    if (ec != std::errc() || ptr != end || id < 0 || !seen.insert(id).second) {
      ids.clear();
      break;
    }
    ids.push_back(id);
  }
  *numeric = !ids.empty();
  if (ids.empty()) {
    for (std::size_t i = 0; i < names.size(); ++i) ids.push_back(static_cast<CameraId>(i));
  }
  return ids;
}

// ---- VoxelPose ---------------------------------------------------------------------------------

// A VoxelPose calibration JSON read with lib/json; every failure is a ConfigError at the file's
// line:column and key path of the offending value.
class VoxelPoseReader : public json::Checker {
 public:
  VoxelPoseReader(const std::string& path, std::string_view text) : path_(path), lines_(text) {}

  [[noreturn]] void Throw(const json::Error& e) const {
    const json::LineColumn at = lines_.At(e.column);
    throw ConfigError(
        path_, static_cast<int>(at.line), static_cast<int>(at.column), e.path, e.reason);
  }
  [[noreturn]] void Throw() const { Throw(error()); }
  [[noreturn]] void Throw(const json::Value& at, const std::string& key, std::string reason) {
    Fail(at, key, std::move(reason));
    Throw();
  }

  double Number(const json::Value& v, const std::string& key) {
    double out = 0.0;
    if (!GetDouble(v, key, &out)) Throw();
    return out;
  }

  // A column of `n` numbers written either as [[a], [b], ...] (VoxelPose) or [a, b, ...].
  std::vector<double> Column(const json::Value& v, const std::string& key, long n) {
    if (!ExpectArray(v, key, n, 0, "a column")) Throw();
    std::vector<double> out;
    for (std::size_t i = 0; i < v.items.size(); ++i) {
      const json::Value& item = v.items[i];
      const std::string item_key = Index(key, i);
      if (item.kind == json::Value::Kind::kArray) {
        if (!ExpectArray(item, item_key, 1, 0, "[value]")) Throw();
        out.push_back(Number(item.items[0], Index(item_key, 0)));
      } else {
        out.push_back(Number(item, item_key));
      }
    }
    return out;
  }

  Mat3 Matrix3(const json::Value& v, const std::string& key) {
    if (!ExpectArray(v, key, 3, 0, "3 rows")) Throw();
    Mat3 m;
    for (std::size_t r = 0; r < 3; ++r) {
      const std::string row_key = Index(key, r);
      if (!ExpectArray(v.items[r], row_key, 3, 0, "a row of 3")) Throw();
      for (std::size_t c = 0; c < 3; ++c) {
        m(static_cast<int>(r), static_cast<int>(c)) =
            Number(v.items[r].items[c], Index(row_key, c));
      }
    }
    return m;
  }

 private:
  const std::string& path_;
  json::LineIndex lines_;
};

}  // namespace

ImageSize ParseImageSize(const std::string& text, const std::string& source_name) {
  const std::size_t x = text.find('x');
  auto parse = [&](std::string_view part) {
    int v = 0;
    const auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
    if (part.empty() || ec != std::errc() || ptr != part.data() + part.size() || v < 1 ||
        v > kMaxImageSidePx) {
      Fail(source_name,
           "",
           "image size '" + text + "' is not WIDTHxHEIGHT with sides in [1, " +
               std::to_string(kMaxImageSidePx) + "] (e.g. 1920x1080)");
    }
    return v;
  };
  if (x == std::string::npos) parse("");
  const std::string_view all(text);
  return ImageSize{parse(all.substr(0, x)), parse(all.substr(x + 1))};
}

ImportedCalibration ImportEasyMocap(const std::string& intri_path,
                                    const std::string& extri_path,
                                    const ImageSize& image_size) {
  const Storage intri(intri_path);
  const Storage extri(extri_path);
  const std::vector<std::string> names = intri.Names("names");
  if (extri.Has("names")) {
    const std::vector<std::string> extri_names = extri.Names("names");
    const std::set<std::string> listed(extri_names.begin(), extri_names.end());
    for (const std::string& name : names) {
      if (!listed.count(name)) {
        Fail(extri.path(), "names", "camera '" + name + "' of " + intri.path() + " is not listed");
      }
    }
  }
  bool numeric = false;
  const std::vector<CameraId> ids = IdsFromNames(names, &numeric);
  ImportedCalibration out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    geometry::CameraModel cam;
    cam.id = ids[i];
    cam.K = ToMat3(intri.Matrix("K_" + name, 3, 3));
    const std::string dist_key = "dist_" + name;
    if (intri.Has(dist_key)) {
      cam.distortion = ToDistortion(intri.Vector(dist_key, {4, 5, 8}), intri.path(), dist_key);
    } else {
      out.notes.push_back("camera '" + name + "': no " + dist_key + " in " + intri.path() +
                          ", no distortion assumed");
    }
    const bool has_w = intri.Has("W_" + name);
    const bool has_h = intri.Has("H_" + name);
    if (has_w != has_h) {
      Fail(intri.path(),
           has_w ? "H_" + name : "W_" + name,
           "missing entry (W_ and H_ come together)");
    }
    if (has_w) {
      cam.width_px = intri.PositiveInt("W_" + name);
      cam.height_px = intri.PositiveInt("H_" + name);
      if (image_size.given() &&
          (image_size.width_px != cam.width_px || image_size.height_px != cam.height_px)) {
        Fail(intri.path(),
             "W_" + name,
             "the file says " + std::to_string(cam.width_px) + "x" + std::to_string(cam.height_px) +
                 " but the given image size is " + std::to_string(image_size.width_px) + "x" +
                 std::to_string(image_size.height_px));
      }
    } else if (image_size.given()) {
      cam.width_px = image_size.width_px;
      cam.height_px = image_size.height_px;
    } else {
      Fail(intri.path(),
           "W_" + name,
           "no image size in the file (W_<name>, H_<name>): give it (--image-size WxH)");
    }
    const std::string rot_key = "Rot_" + name;
    const std::string rvec_key = "R_" + name;
    if (!extri.Has(rot_key) && !extri.Has(rvec_key)) {
      Fail(extri.path(), rot_key, "missing entry (neither Rot_" + name + " nor R_" + name + ")");
    }
    std::optional<Mat3> from_rvec;
    if (extri.Has(rvec_key)) {
      const std::vector<double> r = extri.Vector(rvec_key, {3});
      from_rvec = geometry::RotationFromRodrigues(Vec3(r[0], r[1], r[2]));
    }
    if (extri.Has(rot_key)) {
      cam.cam_from_world.rotation = ToMat3(extri.Matrix(rot_key, 3, 3));
      if (from_rvec &&
          (*from_rvec - cam.cam_from_world.rotation).cwiseAbs().maxCoeff() > kRotationAgreement) {
        Fail(extri.path(),
             rot_key,
             "differs from Rodrigues(" + rvec_key + ") by more than 1e-6 (which one is right?)");
      }
    } else {
      cam.cam_from_world.rotation = *from_rvec;
    }
    const std::vector<double> t = extri.Vector("T_" + name, {3});
    cam.cam_from_world.translation = Vec3(t[0], t[1], t[2]);
    ValidateCamera(cam, intri.path(), "camera '" + name + "'");
    out.document.cameras.push_back(cam);
    out.document.names[cam.id] = name;
  }
  out.notes.push_back(numeric ? "camera ids are the decimal values of the EasyMocap names"
                              : "camera ids are the positions of the names in `names` (0, 1, ...)");
  out.notes.push_back("T_<name> taken as metres (EasyMocap's unit); x_cam = R X + T");
  return out;
}

ImportedCalibration ImportFourDAssociation(const std::string& path) {
  ImportedCalibration out =
      FromDataset(RunDatasetParser([&] { return datasets::LoadShelfCalibrationFile(path); }));
  out.notes.push_back("4D Association: RT is world->camera in metres; no distortion");
  return out;
}

ImportedCalibration ImportVoxelPose(const std::string& path, const ImageSize& image_size) {
  if (!image_size.given()) {
    Fail(path,
         "",
         "VoxelPose calibrations carry no image size: give it (--image-size WxH; Shelf "
         "1032x776, Campus 360x288)");
  }
  const std::string text = internal::ReadTextFile(path);
  VoxelPoseReader reader(path, text);
  json::Error error;
  const std::optional<json::Value> root = json::Parse(text, 16, &error);
  if (!root.has_value()) reader.Throw(error);
  if (root->kind != json::Value::Kind::kObject) {
    reader.Throw(*root, "", "expected an object of cameras keyed by id");
  }
  ImportedCalibration out;
  std::map<CameraId, geometry::CameraModel> by_id;
  int orthonormalized = 0;
  for (const json::Member& member : root->members) {
    const std::string& key = member.key;
    const json::Value& cam_node = *member.value;
    CameraId id = -1;
    const auto [ptr, ec] = std::from_chars(key.data(), key.data() + key.size(), id);
    if (ec != std::errc() || ptr != key.data() + key.size() || id < 0) {
      reader.Throw(json::Error{
          member.key_column, key, "camera key '" + key + "' is not a non-negative integer"});
    }
    std::map<std::string, const json::Value*> cam;
    if (!reader.Members(cam_node,
                        key,
                        {"R", "T", "fx", "fy", "cx", "cy", "k", "p"},
                        {"R", "T", "fx", "fy", "cx", "cy"},
                        &cam)) {
      reader.Throw();
    }
    auto field = [&](const char* name) { return json::Checker::Join(key, name); };
    geometry::CameraModel c;
    c.id = id;
    c.width_px = image_size.width_px;
    c.height_px = image_size.height_px;
    c.K << reader.Number(*cam.at("fx"), field("fx")), 0.0,
        reader.Number(*cam.at("cx"), field("cx")),  //
        0.0, reader.Number(*cam.at("fy"), field("fy")),
        reader.Number(*cam.at("cy"), field("cy")),  //
        0.0, 0.0, 1.0;
    if (cam.count("k") != 0) {
      const std::vector<double> v = reader.Column(*cam.at("k"), field("k"), 3);
      c.distortion.k1 = v[0];
      c.distortion.k2 = v[1];
      c.distortion.k3 = v[2];
    }
    if (cam.count("p") != 0) {
      const std::vector<double> v = reader.Column(*cam.at("p"), field("p"), 2);
      c.distortion.p1 = v[0];
      c.distortion.p2 = v[1];
    }
    bool rounded = false;
    const Mat3 R = NearestRotation(reader.Matrix3(*cam.at("R"), field("R")), &rounded);
    if (rounded) ++orthonormalized;
    const std::vector<double> T = reader.Column(*cam.at("T"), field("T"), 3);
    const Vec3 centre_m = kMmToM * Vec3(T[0], T[1], T[2]);
    c.cam_from_world.rotation = R;
    c.cam_from_world.translation = -(R * centre_m);
    std::string why;
    if (!c.Validate(&why)) reader.Throw(cam_node, key, why);
    if (!by_id.emplace(id, c).second)
      reader.Throw(cam_node, key, "camera " + key + " appears twice");
  }
  if (by_id.empty()) reader.Throw(*root, "", "no cameras");
  for (auto& [id, camera] : by_id) out.document.cameras.push_back(camera);
  out.notes.push_back(
      "VoxelPose: T is the camera centre in mm (x_cam = R (X - T)); converted to "
      "t = -R T / 1000 m");
  if (orthonormalized > 0) {
    out.notes.push_back(std::to_string(orthonormalized) +
                        " rotation(s) rounded in the file (R^T R off I by <= 1e-4) replaced by the "
                        "nearest rotation");
  }
  out.notes.push_back("image size " + std::to_string(image_size.width_px) + "x" +
                      std::to_string(image_size.height_px) + " as given (not in the file)");
  return out;
}

ImportedCalibration ImportPanoptic(const std::string& path,
                                   const std::vector<std::string>& cameras) {
  ImportedCalibration out = FromDataset(
      RunDatasetParser([&] { return datasets::LoadPanopticCalibrationFile(path, cameras); }));
  for (const geometry::CameraModel& c : out.document.cameras) {
    out.document.names[c.id] = (c.id < 10 ? "00_0" : "00_") + std::to_string(c.id);
  }
  out.notes.push_back(
      "Panoptic: HD cameras only; world rotated from y down to z up "
      "((x, y, z) -> (x, z, -y)) and cm -> m, as `mvtrack convert panoptic`");
  return out;
}

ImportedCalibration ImportWildtrack(const std::string& path, const ImageSize& image_size) {
  const ImageSize size = image_size.given() ? image_size : kWildtrackImageSize;
  std::error_code ec;
  ImportedCalibration out;
  if (std::filesystem::is_regular_file(path, ec)) {
    out =
        FromDataset(RunDatasetParser([&] { return datasets::LoadWildtrackCalibrationFile(path); }));
    if (image_size.given()) {
      for (geometry::CameraModel& c : out.document.cameras) {
        c.width_px = size.width_px;
        c.height_px = size.height_px;
      }
    }
    if (out.document.cameras.size() == kWildtrackNames.size()) {
      for (std::size_t i = 0; i < kWildtrackNames.size(); ++i) {
        out.document.names[out.document.cameras[i].id] = kWildtrackNames[i];
      }
    }
    out.notes.push_back("WILDTRACK derived JSON: tvec in cm -> m, ground plane z = 0");
    return out;
  }
  if (!std::filesystem::is_directory(path, ec)) Fail(path, "", "no such file or directory");
  std::filesystem::path dir = path;
  if (std::filesystem::is_directory(dir / "calibrations", ec)) dir /= "calibrations";
  const std::filesystem::path intr_dir = dir / "intrinsic_zero";
  const std::filesystem::path extr_dir = dir / "extrinsic";
  if (!std::filesystem::is_directory(intr_dir, ec) ||
      !std::filesystem::is_directory(extr_dir, ec)) {
    Fail(path,
         "",
         "expected the WILDTRACK folders intrinsic_zero/ and extrinsic/ (in it or in its "
         "calibrations/ folder), or the derived calibration JSON file");
  }
  std::vector<std::string> found;
  for (const auto& entry : std::filesystem::directory_iterator(intr_dir, ec)) {
    const std::string file = entry.path().filename().string();
    if (file.size() > 9 && file.rfind("intr_", 0) == 0 &&
        file.compare(file.size() - 4, 4, ".xml") == 0) {
      found.push_back(file.substr(5, file.size() - 9));
    }
  }
  if (ec) Fail(intr_dir.string(), "", "cannot list the folder: " + ec.message());
  if (found.empty()) Fail(intr_dir.string(), "", "no intr_<name>.xml files");
  std::sort(found.begin(), found.end());
  std::vector<std::string> names;
  if (found == std::vector<std::string>(kWildtrackNames.begin(), kWildtrackNames.end())) {
    names = kWildtrackNames;  // the dataset's order C1..C7 (already sorted, stated for clarity)
  } else {
    names = found;
  }
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    const Storage intr((intr_dir / ("intr_" + name + ".xml")).string());
    const std::filesystem::path extr_path = extr_dir / ("extr_" + name + ".xml");
    if (!std::filesystem::exists(extr_path, ec)) {
      Fail(extr_path.string(),
           "",
           "file does not exist (intrinsics of camera " + name + " have no extrinsics)");
    }
    const Storage extr(extr_path.string());
    geometry::CameraModel cam;
    cam.id = static_cast<CameraId>(i);
    cam.width_px = size.width_px;
    cam.height_px = size.height_px;
    cam.K = ToMat3(intr.Matrix("camera_matrix", 3, 3));
    cam.distortion = ToDistortion(
        intr.Vector("distortion_coefficients", {4, 5, 8}), intr.path(), "distortion_coefficients");
    const std::vector<double> r = extr.Vector("rvec", {3});
    const std::vector<double> t = extr.Vector("tvec", {3});
    cam.cam_from_world.rotation = geometry::RotationFromRodrigues(Vec3(r[0], r[1], r[2]));
    cam.cam_from_world.translation = kCmToM * Vec3(t[0], t[1], t[2]);
    ValidateCamera(cam, intr.path(), "camera " + name);
    out.document.cameras.push_back(cam);
    out.document.names[cam.id] = name;
  }
  out.notes.push_back(
      "WILDTRACK XML: intrinsic_zero (for the undistorted images), rvec "
      "Rodrigues, tvec in cm -> m, ground plane z = 0");
  out.notes.push_back("image size " + std::to_string(size.width_px) + "x" +
                      std::to_string(size.height_px) +
                      (image_size.given() ? " as given" : " (WILDTRACK's; not in the files)"));
  return out;
}

ImportedHomographies ImportFloorHomographies(const std::vector<std::string>& paths,
                                             const HomographyImportOptions& options) {
  if (paths.empty()) Fail("", "", "no homography files (one per camera)");
  if (!options.image_size.given()) {
    Fail(paths.front(), "", "homography files carry no image size: give it (--image-size WxH)");
  }
  geometry::FloorHomographyOptions camera_options;
  camera_options.floor_unit_m = options.floor_unit_m.value_or(1.0);
  camera_options.focal_px = options.focal_px;
  camera_options.principal_point_px = options.principal_point_px;
  std::string why;
  if (!camera_options.Validate(&why)) Fail(paths.front(), "", why);
  ImportedHomographies out;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const CameraId id = static_cast<CameraId>(i);
    const Mat3 h = RunDatasetParser([&] { return datasets::LoadFloorHomographyFile(paths[i]); });
    geometry::FloorHomographyCamera r = geometry::CameraFromFloorHomography(
        h, id, options.image_size.width_px, options.image_size.height_px, camera_options);
    if (!r.ok) Fail(paths[i], "camera " + std::to_string(id), r.reason);
    out.checks.push_back(std::move(r));
  }
  const geometry::FloorHomographyCamera& first = out.checks.front();
  for (std::size_t i = 1; i < out.checks.size(); ++i) {
    if (out.checks[i].mirrored_y != first.mirrored_y) {
      Fail(paths[i],
           "camera " + std::to_string(i),
           std::string("needs the floor's y axis ") + (out.checks[i].mirrored_y ? "" : "not ") +
               "mirrored to make the world right-handed with z up, camera 0 (" + paths.front() +
               ") the opposite: the homographies do not share one floor frame (is one of them "
               "floor -> image?)");
    }
  }
  std::string focals;
  for (const geometry::FloorHomographyCamera& c : out.checks) {
    out.calibration.document.cameras.push_back(c.camera);
    char buffer[96];
    if (c.focal_estimated) {
      std::snprintf(buffer,
                    sizeof(buffer),
                    "%s%d: %.1f px (closed form %.1f)",
                    focals.empty() ? "" : ", ",
                    c.camera.id,
                    c.focal_px,
                    c.initial_focal_px);
    } else {
      std::snprintf(buffer,
                    sizeof(buffer),
                    "%s%d: %.1f px",
                    focals.empty() ? "" : ", ",
                    c.camera.id,
                    c.focal_px);
    }
    focals += buffer;
  }
  std::vector<std::string>& notes = out.calibration.notes;
  notes.push_back(
      "homography: H maps image (u, v, 1) to floor (x, y, 1); each camera recovered from "
      "H^-1 = s K [r1 r2 t] assuming square pixels, zero skew, no distortion, the principal "
      "point " +
      std::string(options.principal_point_px ? "as given" : "at the image centre") +
      "; R = the nearest rotation of [r1 r2 r1 x r2]; the sign of s puts the floor in front of "
      "the camera; world z up, the floor at z = 0; then R, t" +
      std::string(options.focal_px ? "" : " and f") +
      " refined to minimise the floor reprojection error over an 11 x 11 pixel grid");
  notes.push_back(std::string("focal length ") +
                  (options.focal_px ? "as given"
                                    : "from each homography's orthogonality constraints (least "
                                      "squares), refined") +
                  ": " + focals);
  if (options.floor_unit_m) {
    char buffer[96];
    std::snprintf(buffer, sizeof(buffer), "floor unit %.6g m as given", *options.floor_unit_m);
    notes.push_back(buffer);
  } else {
    notes.push_back(
        "floor unit taken as 1 m (no --floor-unit given): if the homographies' floor is in "
        "another unit (cm, mm, grid cells), every distance is off by that factor");
  }
  notes.push_back(first.mirrored_y
                      ? "the floor's (x, y) with z up is a left-handed frame: y mirrored (world "
                        "y = -floor y) so that the world is right-handed with z up"
                      : "the floor's (x, y) with z up is right-handed: world x, y = floor x, y");
  notes.push_back("image size " + std::to_string(options.image_size.width_px) + "x" +
                  std::to_string(options.image_size.height_px) + " as given (not in the files)");
  return out;
}

ImportedCalibration ImportCampus(const std::string& path, const ImageSize& image_size) {
  const ImageSize size = image_size.given() ? image_size : kCampusImageSize;
  ImportedCalibration out = FromDataset(RunDatasetParser(
      [&] { return datasets::LoadCampusCalibrationFile(path, size.width_px, size.height_px); }));
  out.notes.push_back("Campus (Cross-View Tracking): K de-normalised by the image size " +
                      std::to_string(size.width_px) + "x" + std::to_string(size.height_px) +
                      ", Tw camera->world with the centre in cm; dist_coeffs not applied");
  return out;
}

}  // namespace mvtrack::config
