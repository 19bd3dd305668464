#include "config/calibration.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <optional>
#include <utility>

#include "config/internal/calibration_node.h"
#include "config/internal/yaml_node.h"

namespace mvtrack::config {
namespace {

using internal::DoubleRange;
using internal::FormatDouble;
using internal::GetDouble;
using internal::GetInt;
using internal::GetSequence;
using internal::GetString;
using internal::kMaxImageSidePx;
using internal::MapRef;
using internal::NodeRef;

// The intrinsic scalars of the alternative to `K`.
const std::vector<std::string> kIntrinsicScalars = {"fx", "fy", "cx", "cy", "skew"};

Mat3 GetMat3(const NodeRef& node) {
  Mat3 m;
  const std::vector<NodeRef> rows = GetSequence(node, 3);
  for (int r = 0; r < 3; ++r) {
    const std::vector<NodeRef> cols = GetSequence(rows[static_cast<std::size_t>(r)], 3);
    for (int c = 0; c < 3; ++c) m(r, c) = GetDouble(cols[static_cast<std::size_t>(c)]);
  }
  return m;
}

Vec3 GetVec3(const NodeRef& node) {
  const std::vector<NodeRef> values = GetSequence(node, 3);
  return Vec3(GetDouble(values[0]), GetDouble(values[1]), GetDouble(values[2]));
}

// Runs CameraModel::Validate on a camera that is valid except for the part being checked, so a
// failure can be reported at the key that holds that part.
void CheckPart(const geometry::CameraModel& probe, const NodeRef& where, const std::string& hint) {
  std::string why;
  if (!probe.Validate(&why)) where.Fail(why + hint);
}

geometry::CameraModel MinimalCamera(CameraId id) {
  geometry::CameraModel camera;
  camera.id = id;
  camera.width_px = 1;
  camera.height_px = 1;
  return camera;
}

// Parses one entry of `cameras`; `id_node` receives the position of its id (for duplicates).
geometry::CameraModel ParseCamera(const NodeRef& node,
                                  std::optional<std::string>* name,
                                  std::optional<NodeRef>* id_node) {
  const MapRef map(node,
                   {"id",
                    "name",
                    "image_size",
                    "K",
                    "fx",
                    "fy",
                    "cx",
                    "cy",
                    "skew",
                    "distortion",
                    "R",
                    "rvec",
                    "t"});
  geometry::CameraModel camera;
  id_node->emplace(map.Get("id"));
  camera.id = GetInt(**id_node, 0, std::numeric_limits<CameraId>::max());
  if (const std::optional<NodeRef> name_node = map.Find("name")) *name = GetString(*name_node);

  const std::vector<NodeRef> size = GetSequence(map.Get("image_size"), 2);
  camera.width_px = GetInt(size[0], 1, kMaxImageSidePx);
  camera.height_px = GetInt(size[1], 1, kMaxImageSidePx);

  // Intrinsics: either the matrix K or the scalars fx, fy, cx, cy (+ skew), never both.
  if (map.Has("K")) {
    for (const std::string& key : kIntrinsicScalars) {
      if (map.Has(key)) {
        map.KeyRef(key).Fail(
            "give the intrinsics either as 'K' or as 'fx', 'fy', 'cx', 'cy' "
            "(+ 'skew'), not both");
      }
    }
    const NodeRef k_node = map.Get("K");
    camera.K = GetMat3(k_node);
    geometry::CameraModel probe = MinimalCamera(camera.id);
    probe.K = camera.K;
    CheckPart(probe, k_node, " (K = [[fx, skew, cx], [0, fy, cy], [0, 0, 1]])");
  } else {
    const bool any_scalar = std::any_of(kIntrinsicScalars.begin(),
                                        kIntrinsicScalars.end(),
                                        [&](const std::string& key) { return map.Has(key); });
    if (!any_scalar) {
      map.ref().Fail("missing intrinsics: give 'K' or 'fx', 'fy', 'cx', 'cy' (+ 'skew')");
    }
    camera.K = Mat3::Identity();
    camera.K(0, 0) = GetDouble(map.Get("fx"), DoubleRange::GreaterThan(0.0));
    camera.K(1, 1) = GetDouble(map.Get("fy"), DoubleRange::GreaterThan(0.0));
    camera.K(0, 2) = GetDouble(map.Get("cx"));
    camera.K(1, 2) = GetDouble(map.Get("cy"));
    if (const std::optional<NodeRef> skew = map.Find("skew")) camera.K(0, 1) = GetDouble(*skew);
  }

  if (const std::optional<NodeRef> distortion = map.Find("distortion")) {
    const std::vector<NodeRef> d = GetSequence(*distortion, 5);
    camera.distortion.k1 = GetDouble(d[0]);
    camera.distortion.k2 = GetDouble(d[1]);
    camera.distortion.p1 = GetDouble(d[2]);
    camera.distortion.p2 = GetDouble(d[3]);
    camera.distortion.k3 = GetDouble(d[4]);
  }

  // Extrinsics cam_from_world: a rotation (R or rvec) and t.
  const std::string rotation_key = map.RequireExactlyOne({"R", "rvec"}, "rotation");
  const NodeRef rotation_node = map.Get(rotation_key);
  if (rotation_key == "R") {
    camera.cam_from_world.rotation = GetMat3(rotation_node);
    geometry::CameraModel probe = MinimalCamera(camera.id);
    probe.cam_from_world.rotation = camera.cam_from_world.rotation;
    CheckPart(probe,
              rotation_node,
              " (write R with at least 7 significant digits per entry, or give 'rvec')");
  } else {
    camera.cam_from_world.rotation = geometry::RotationFromRodrigues(GetVec3(rotation_node));
  }
  camera.cam_from_world.translation = GetVec3(map.Get("t"));

  std::string why;
  if (!camera.Validate(&why)) map.ref().Fail(why);
  return camera;
}

void AppendVector(std::string* out, std::initializer_list<double> values) {
  *out += '[';
  bool first = true;
  for (const double v : values) {
    if (!first) *out += ", ";
    *out += FormatDouble(v);
    first = false;
  }
  *out += ']';
}

void AppendMatrix(std::string* out, const Mat3& m) {
  *out += '[';
  for (int r = 0; r < 3; ++r) {
    if (r > 0) *out += ", ";
    AppendVector(out, {m(r, 0), m(r, 1), m(r, 2)});
  }
  *out += ']';
}

// Camera centres farther apart than this, or farther from the floor plane z = 0, cannot be one
// rig of overlapping views in metres: a unit mistake.
constexpr double kMaxRigSpreadM = 1000.0;
constexpr double kMaxCameraHeightM = 100.0;

// Why `cameras` (translations in metres) cannot be a rig in metres, naming the likely unit;
// nullopt when plausible.
std::optional<std::string> ImplausibleScale(const std::vector<geometry::CameraModel>& cameras) {
  double spread = 0.0;
  double height = 0.0;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const Vec3 a = cameras[i].CenterInWorld();
    height = std::max(height, std::abs(a.z()));
    for (std::size_t j = i + 1; j < cameras.size(); ++j) {
      spread = std::max(spread, (a - cameras[j].CenterInWorld()).norm());
    }
  }
  if (spread <= kMaxRigSpreadM && height <= kMaxCameraHeightM) return std::nullopt;
  // A ceiling camera is 2-10 m up: in millimetres that is 2000-10000, in centimetres 200-1000.
  const bool mm = height > 10.0 * kMaxCameraHeightM || spread > 10.0 * kMaxRigSpreadM;
  char text[400];
  std::snprintf(text,
                sizeof text,
                "the cameras are up to %.0f m apart and %.0f m from the floor plane: the "
                "translations t look like %s, not metres; write 'units: %s' to have them "
                "converted (rigs wider than %.0f m or cameras higher than %.0f m are refused as "
                "a unit mistake)",
                spread,
                height,
                mm ? "millimetres" : "centimetres",
                mm ? "mm" : "cm",
                kMaxRigSpreadM,
                kMaxCameraHeightM);
  return std::string(text);
}

}  // namespace

namespace internal {

CalibrationDocument ParseCalibrationNode(const NodeRef& root) {
  if (root.IsNull()) {
    root.Fail("empty calibration (expected a map with 'format: " + std::string(kCalibrationFormat) +
              "' and 'cameras')");
  }
  const MapRef map(root, {"format", "units", "cameras"});
  const NodeRef format = map.Get("format");
  if (GetString(format) != kCalibrationFormat) {
    format.Fail("unsupported format '" + format.node().Scalar() + "' (expected '" +
                std::string(kCalibrationFormat) + "')");
  }
  // Translations in another unit are converted to metres (`units: cm` / `mm`).
  double metres_per_unit = 1.0;
  const std::optional<NodeRef> units = map.Find("units");
  if (units) {
    const std::string unit = GetString(*units);
    if (unit == "cm") {
      metres_per_unit = 0.01;
    } else if (unit == "mm") {
      metres_per_unit = 0.001;
    } else if (unit != "m") {
      units->Fail("unsupported units '" + units->node().Scalar() +
                  "' (m, cm or mm: the unit of every camera's t)");
    }
  }
  const NodeRef cameras_node = map.Get("cameras");
  const std::vector<NodeRef> cameras = GetSequence(cameras_node);
  if (cameras.empty()) cameras_node.Fail("the rig needs at least one camera");

  CalibrationDocument document;
  std::map<CameraId, std::size_t> index_of_id;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    std::optional<std::string> name;
    std::optional<NodeRef> id_node;
    geometry::CameraModel camera = ParseCamera(cameras[i], &name, &id_node);
    const auto [it, inserted] = index_of_id.emplace(camera.id, i);
    if (!inserted) {
      id_node->Fail("duplicate camera id " + std::to_string(camera.id) + " (also used by " +
                    cameras[it->second].path() + " at line " +
                    std::to_string(cameras[it->second].line()) + ")");
    }
    if (name.has_value()) document.names.emplace(camera.id, std::move(*name));
    camera.cam_from_world.translation *= metres_per_unit;
    document.cameras.push_back(std::move(camera));
  }
  if (const std::optional<std::string> why = ImplausibleScale(document.cameras)) {
    (units ? *units : cameras_node).Fail(*why);
  }
  return document;
}

}  // namespace internal

CalibrationDocument ParseCalibrationDocument(std::string_view text,
                                             const std::string& source_name) {
  const NodeRef root = internal::ParseDocument(text, source_name);
  try {
    return internal::ParseCalibrationNode(root);
  } catch (const YAML::Exception& e) {
    // Backstop: the helpers check types before touching yaml-cpp's throwing accessors.
    throw ConfigError(source_name,
                      e.mark.is_null() ? 0 : e.mark.line + 1,
                      e.mark.is_null() ? 0 : e.mark.column + 1,
                      "",
                      e.msg);
  }
}

CalibrationDocument LoadCalibrationDocument(const std::string& path) {
  return ParseCalibrationDocument(internal::ReadTextFile(path), path);
}

std::vector<geometry::CameraModel> ParseCalibration(std::string_view text,
                                                    const std::string& source_name) {
  return ParseCalibrationDocument(text, source_name).cameras;
}

std::vector<geometry::CameraModel> LoadCalibration(const std::string& path) {
  return LoadCalibrationDocument(path).cameras;
}

std::string CalibrationToYaml(const std::vector<geometry::CameraModel>& cameras,
                              const std::map<CameraId, std::string>& names) {
  std::vector<std::size_t> order(cameras.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return cameras[a].id < cameras[b].id;
  });
  std::string out;
  out += "format: " + std::string(kCalibrationFormat) + "\n";
  out += "units: m\n";
  out += "cameras:\n";
  for (const std::size_t index : order) {
    const geometry::CameraModel& c = cameras[index];
    out += "  - id: " + std::to_string(c.id) + "\n";
    if (const auto name = names.find(c.id); name != names.end()) {
      out += "    name: " + internal::QuoteString(name->second) + "\n";
    }
    out += "    image_size: [" + std::to_string(c.width_px) + ", " + std::to_string(c.height_px) +
           "]\n";
    out += "    K: ";
    AppendMatrix(&out, c.K);
    out += "\n    distortion: ";
    AppendVector(
        &out,
        {c.distortion.k1, c.distortion.k2, c.distortion.p1, c.distortion.p2, c.distortion.k3});
    out += "\n    R: ";
    AppendMatrix(&out, c.cam_from_world.rotation);
    out += "\n    t: ";
    const Vec3& t = c.cam_from_world.translation;
    AppendVector(&out, {t.x(), t.y(), t.z()});
    out += "\n";
  }
  return out;
}

void SaveCalibration(const std::string& path,
                     const std::vector<geometry::CameraModel>& cameras,
                     const std::map<CameraId, std::string>& names) {
  if (cameras.empty()) {
    throw ConfigError(path, 0, 0, "cameras", "the rig needs at least one camera");
  }
  std::map<CameraId, std::size_t> index_of_id;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const std::string key_path = "cameras[" + std::to_string(i) + "]";
    std::string why;
    if (!cameras[i].Validate(&why)) throw ConfigError(path, 0, 0, key_path, why);
    const auto [it, inserted] = index_of_id.emplace(cameras[i].id, i);
    if (!inserted) {
      throw ConfigError(path,
                        0,
                        0,
                        key_path + ".id",
                        "duplicate camera id " + std::to_string(cameras[i].id) +
                            " (also used by cameras[" + std::to_string(it->second) + "])");
    }
  }
  internal::WriteTextFile(path, CalibrationToYaml(cameras, names));
}

}  // namespace mvtrack::config
