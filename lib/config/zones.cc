#include "config/zones.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include "config/internal/yaml_node.h"
#include "core/check.h"

namespace mvtrack::config {
namespace {

// Splits `ids` (indices into `pos`) into `parts` parts of nearly equal size along the longer
// extent of their positions, recursively; appends the parts to `out` in order.
void Split(std::vector<int> ids,
           int parts,
           const std::vector<Vec2>& pos,
           const std::vector<CameraId>& camera_ids,
           std::vector<std::vector<int>>* out) {
  if (parts <= 1 || ids.size() <= 1) {
    out->push_back(std::move(ids));
    return;
  }
  Vec2 lo = pos[static_cast<std::size_t>(ids.front())];
  Vec2 hi = lo;
  for (const int i : ids) {
    lo = lo.cwiseMin(pos[static_cast<std::size_t>(i)]);
    hi = hi.cwiseMax(pos[static_cast<std::size_t>(i)]);
  }
  const int axis = (hi.x() - lo.x()) >= (hi.y() - lo.y()) ? 0 : 1;
  std::sort(ids.begin(), ids.end(), [&](int a, int b) {
    const double pa = pos[static_cast<std::size_t>(a)][axis];
    const double pb = pos[static_cast<std::size_t>(b)][axis];
    if (pa != pb) return pa < pb;
    return camera_ids[static_cast<std::size_t>(a)] < camera_ids[static_cast<std::size_t>(b)];
  });
  const int left_parts = parts / 2;
  const auto left_n = static_cast<std::size_t>(
      std::lround(static_cast<double>(ids.size()) * left_parts / static_cast<double>(parts)));
  std::vector<int> left(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(left_n));
  std::vector<int> right(ids.begin() + static_cast<std::ptrdiff_t>(left_n), ids.end());
  Split(std::move(left), left_parts, pos, camera_ids, out);
  Split(std::move(right), parts - left_parts, pos, camera_ids, out);
}

}  // namespace

bool ZoneOptions::Validate(std::string* why) const {
  auto fail = [&](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (max_cameras < 2) return fail("max_cameras must be >= 2");
  if (!(cell_m > 0.0) || !std::isfinite(cell_m)) return fail("cell_m must be finite and > 0");
  if (!std::isfinite(sample_height_m)) return fail("sample_height_m must be finite");
  if (!(min_shared_area_m2 >= 0.0) || !std::isfinite(min_shared_area_m2)) {
    return fail("min_shared_area_m2 must be finite and >= 0");
  }
  return true;
}

std::optional<std::string> ValidateZoneName(std::string_view name) {
  if (name.empty() || name.size() > 32 || !std::all_of(name.begin(), name.end(), [](char ch) {
        return (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_';
      })) {
    return std::string("a zone name has 1 to 32 characters a-z, 0-9 and _ (it names channels)");
  }
  return std::nullopt;
}

std::vector<Zone> ParseZones(std::string_view text, const std::string& source_name) {
  using internal::GetSequence;
  using internal::GetString;
  using internal::MapRef;
  using internal::NodeRef;
  const NodeRef root_node = internal::ParseDocument(text, source_name);
  if (root_node.IsNull()) {
    root_node.Fail("empty document (expected a map with 'format: " + std::string(kZonesFormat) +
                   "')");
  }
  const MapRef root(root_node, {"format", "zones"});
  const NodeRef format = root.Get("format");
  if (GetString(format) != kZonesFormat) {
    format.Fail("expected '" + std::string(kZonesFormat) + "', not '" + GetString(format) + "'");
  }
  const NodeRef list = root.Get("zones");
  const std::vector<NodeRef> items = GetSequence(list);
  if (items.empty()) list.Fail("a site needs at least one zone");
  if (items.size() > static_cast<std::size_t>(kMaxZones)) {
    list.Fail("a site has at most " + std::to_string(kMaxZones) + " zones, not " +
              std::to_string(items.size()));
  }
  std::vector<Zone> zones;
  std::map<CameraId, std::string> owner;  // camera -> the zone that owns it
  std::vector<std::pair<NodeRef, std::string>> neighbour_refs;
  const auto camera_list = [](const NodeRef& node) {
    std::vector<CameraId> ids;
    for (const NodeRef& item : GetSequence(node)) {
      const auto id = static_cast<CameraId>(internal::GetInt64(item, 0, 2147483647));
      if (std::find(ids.begin(), ids.end(), id) != ids.end()) {
        item.Fail("camera " + std::to_string(id) + " is listed twice");
      }
      ids.push_back(id);
    }
    std::sort(ids.begin(), ids.end());
    return ids;
  };
  for (const NodeRef& item : items) {
    const MapRef m(item, {"name", "cameras", "border_cameras", "neighbours", "daemon"});
    Zone z;
    const NodeRef name = m.Get("name");
    z.name = GetString(name);
    if (const std::optional<std::string> why = ValidateZoneName(z.name)) name.Fail(*why);
    for (const Zone& other : zones) {
      if (other.name == z.name) name.Fail("another zone is named '" + z.name + "'");
    }
    const NodeRef cameras = m.Get("cameras");
    z.cameras = camera_list(cameras);
    if (z.cameras.empty()) cameras.Fail("a zone needs at least one camera of its own");
    for (const CameraId id : z.cameras) {
      if (const auto it = owner.find(id); it != owner.end()) {
        cameras.Fail("camera " + std::to_string(id) + " is zone '" + it->second +
                     "''s already (a camera belongs to one zone; list it under border_cameras)");
      }
      owner[id] = z.name;
    }
    if (const std::optional<NodeRef> border = m.Find("border_cameras")) {
      z.border = camera_list(*border);
      for (const CameraId id : z.border) {
        if (std::binary_search(z.cameras.begin(), z.cameras.end(), id)) {
          border->Fail("camera " + std::to_string(id) + " is one of the zone's own cameras");
        }
      }
    }
    if (const std::optional<NodeRef> neighbours = m.Find("neighbours")) {
      for (const NodeRef& n : GetSequence(*neighbours)) {
        z.neighbours.push_back(GetString(n));
        neighbour_refs.emplace_back(n, z.neighbours.back());
      }
    }
    if (const std::optional<NodeRef> daemon = m.Find("daemon")) z.daemon = GetString(*daemon);
    zones.push_back(std::move(z));
  }
  for (const auto& [ref, neighbour] : neighbour_refs) {
    if (std::none_of(
            zones.begin(), zones.end(), [&](const Zone& z) { return z.name == neighbour; })) {
      ref.Fail("no zone is named '" + neighbour + "'");
    }
  }
  return zones;
}

std::vector<Zone> LoadZonesFile(const std::string& path) {
  return ParseZones(internal::ReadTextFile(path), path);
}

std::string ZonesToYaml(const std::vector<Zone>& zones, const std::string& comment) {
  const auto ids = [](const std::vector<CameraId>& v) {
    std::string s;
    for (const CameraId id : v) s += (s.empty() ? "" : ", ") + std::to_string(id);
    return "[" + s + "]";
  };
  std::string out;
  if (!comment.empty()) out += "# " + comment + "\n";
  out += "format: " + std::string(kZonesFormat) + "\nzones:\n";
  for (const Zone& z : zones) {
    std::string neighbours;
    for (const std::string& n : z.neighbours) neighbours += (neighbours.empty() ? "" : ", ") + n;
    out += "  - name: " + z.name + "\n    cameras: " + ids(z.cameras) +
           "\n    border_cameras: " + ids(z.border) + "\n    neighbours: [" + neighbours + "]\n";
    if (!z.daemon.empty()) out += "    daemon: " + internal::QuoteString(z.daemon) + "\n";
  }
  return out;
}

std::vector<std::string> ZoneNames(const std::vector<Zone>& zones) {
  std::vector<std::string> names;
  names.reserve(zones.size());
  for (const Zone& z : zones) names.push_back(z.name);
  return names;
}

std::string ZoneChannel(const std::string& channel, const std::string& zone) {
  std::string upper = zone;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return channel + "_" + upper;
}

std::vector<Zone> PartitionZones(const std::vector<geometry::CameraModel>& cameras,
                                 const ZoneOptions& options) {
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), "invalid ZoneOptions");
  MVTRACK_CHECK_MSG(cameras.size() >= 2, "PartitionZones needs at least 2 cameras");
  const std::size_t n = cameras.size();
  // Each camera's cells of the floor grid, and its position for the split.
  const FloorRegion region = DefaultFloorRegion(cameras, options.sample_height_m, 1.0);
  const int cols = std::max(1, static_cast<int>(std::ceil(region.width_m() / options.cell_m)));
  const int rows = std::max(1, static_cast<int>(std::ceil(region.depth_m() / options.cell_m)));
  std::vector<std::vector<int>> cells(n);
  std::vector<Vec2> pos(n);
  std::vector<CameraId> ids(n);
  for (std::size_t c = 0; c < n; ++c) {
    ids[c] = cameras[c].id;
    Vec2 sum = Vec2::Zero();
    for (int r = 0; r < rows; ++r) {
      for (int k = 0; k < cols; ++k) {
        const Vec3 p(region.x_min_m + (k + 0.5) * options.cell_m,
                     region.y_min_m + (r + 0.5) * options.cell_m,
                     options.sample_height_m);
        if (!geometry::SeesPoint(cameras[c], p)) continue;
        cells[c].push_back(r * cols + k);
        sum += p.head<2>();
      }
    }
    pos[c] = cells[c].empty() ? Vec2(cameras[c].CenterInWorld().head<2>())
                              : Vec2(sum / static_cast<double>(cells[c].size()));
  }
  const auto per_zone = static_cast<std::size_t>(options.max_cameras);
  const int parts = static_cast<int>((n + per_zone - 1) / per_zone);
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  std::vector<std::vector<int>> groups;
  Split(std::move(all), parts, pos, ids, &groups);

  const double cell_area = options.cell_m * options.cell_m;
  std::vector<Zone> zones(groups.size());
  std::vector<int> zone_of(n, -1);
  std::vector<std::vector<char>> covered(groups.size());  // per zone: cells its cameras see
  for (std::size_t z = 0; z < groups.size(); ++z) {
    Zone& zone = zones[z];
    zone.name = "zone" + std::to_string(z + 1);
    covered[z].assign(static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols), 0);
    bool any = false;
    for (const int c : groups[z]) {
      zone_of[static_cast<std::size_t>(c)] = static_cast<int>(z);
      zone.cameras.push_back(ids[static_cast<std::size_t>(c)]);
      for (const int cell : cells[static_cast<std::size_t>(c)]) {
        covered[z][static_cast<std::size_t>(cell)] = 1;
      }
    }
    std::sort(zone.cameras.begin(), zone.cameras.end());
    // Grows the zone's bounds to hold [x0, x1] x [y0, y1].
    const auto grow = [&zone, &any](double x0, double y0, double x1, double y1) {
      if (!any) zone.bounds = FloorRegion{x0, y0, x1, y1};
      any = true;
      zone.bounds.x_min_m = std::min(zone.bounds.x_min_m, x0);
      zone.bounds.y_min_m = std::min(zone.bounds.y_min_m, y0);
      zone.bounds.x_max_m = std::max(zone.bounds.x_max_m, x1);
      zone.bounds.y_max_m = std::max(zone.bounds.y_max_m, y1);
    };
    for (std::size_t cell = 0; cell < covered[z].size(); ++cell) {
      if (covered[z][cell] == 0) continue;
      const double x =
          region.x_min_m +
          (static_cast<double>(cell % static_cast<std::size_t>(cols)) + 0.5) * options.cell_m;
      const double y =
          region.y_min_m +
          (static_cast<double>(cell / static_cast<std::size_t>(cols)) + 0.5) * options.cell_m;
      const double h = 0.5 * options.cell_m;
      grow(x - h, y - h, x + h, y + h);
      zone.area_m2 += cell_area;
    }
    if (!any) {
      for (const int c : groups[z]) {
        const Vec3 center = cameras[static_cast<std::size_t>(c)].CenterInWorld();
        grow(center.x(), center.y(), center.x(), center.y());
      }
    }
  }
  // Border cameras: another zone's camera that sees enough of this zone's floor.
  std::vector<std::set<int>> neighbours(zones.size());
  for (std::size_t z = 0; z < zones.size(); ++z) {
    std::vector<char> shared(covered[z].size(), 0);
    for (std::size_t c = 0; c < n; ++c) {
      if (zone_of[c] == static_cast<int>(z)) continue;
      std::size_t common = 0;
      for (const int cell : cells[c])
        common += covered[z][static_cast<std::size_t>(cell)] != 0 ? 1 : 0;
      if (static_cast<double>(common) * cell_area < options.min_shared_area_m2 || common == 0) {
        continue;
      }
      zones[z].border.push_back(ids[c]);
      for (const int cell : cells[c]) {
        if (covered[z][static_cast<std::size_t>(cell)] != 0)
          shared[static_cast<std::size_t>(cell)] = 1;
      }
      neighbours[z].insert(zone_of[c]);
      neighbours[static_cast<std::size_t>(zone_of[c])].insert(static_cast<int>(z));
    }
    std::sort(zones[z].border.begin(), zones[z].border.end());
    zones[z].border_area_m2 =
        static_cast<double>(std::count(shared.begin(), shared.end(), 1)) * cell_area;
  }
  for (std::size_t z = 0; z < zones.size(); ++z) {
    for (const int other : neighbours[z])
      zones[z].neighbours.push_back(zones[static_cast<std::size_t>(other)].name);
  }
  return zones;
}

}  // namespace mvtrack::config
