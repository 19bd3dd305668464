#include "config/site.h"

#include <yaml-cpp/yaml.h>

#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "config/internal/yaml_node.h"

namespace mvtrack::config {
namespace {

using internal::DoubleRange;
using internal::GetDouble;
using internal::GetSequence;
using internal::GetString;
using internal::MapRef;
using internal::NodeRef;

// Coordinates on the floor are metres; anything beyond this is a typo (or hostile input).
constexpr double kMaxCoordinateM = 1e6;

Vec2 GetPoint(const NodeRef& node) {
  const std::vector<NodeRef> xy = GetSequence(node, 2);
  const DoubleRange range = DoubleRange::Closed(-kMaxCoordinateM, kMaxCoordinateM);
  return {GetDouble(xy[0], range), GetDouble(xy[1], range)};
}

// A name: non-empty, unique among `names` (regions and lines have their own).
std::string GetName(const NodeRef& node, std::set<std::string>* names, const char* what) {
  std::string name = GetString(node);
  if (const std::optional<std::string> why = analytics::ValidateName(name)) node.Fail(*why);
  if (!names->insert(name).second)
    node.Fail("another " + std::string(what) + " is named '" + name + "'");
  return name;
}

}  // namespace

analytics::Site ParseSite(std::string_view text, const std::string& source_name) {
  const NodeRef root_node = internal::ParseDocument(text, source_name);
  if (root_node.IsNull()) {
    root_node.Fail("empty document (expected a map with 'format: " + std::string(kSiteFormat) +
                   "')");
  }
  analytics::Site site;
  const MapRef root(root_node, {"format", "regions", "lines", "rules"});
  const NodeRef format = root.Get("format");
  if (GetString(format) != kSiteFormat) {
    format.Fail("expected '" + std::string(kSiteFormat) + "', not '" + GetString(format) + "'");
  }
  if (const std::optional<NodeRef> regions = root.Find("regions")) {
    const std::vector<NodeRef> items = GetSequence(*regions);
    if (items.size() > static_cast<std::size_t>(analytics::kMaxRegions)) {
      regions->Fail("more than " + std::to_string(analytics::kMaxRegions) + " regions");
    }
    std::set<std::string> names;
    for (const NodeRef& item : items) {
      const MapRef region(item, {"name", "polygon"});
      analytics::Region r;
      r.name = GetName(region.Get("name"), &names, "region");
      const NodeRef polygon = region.Get("polygon");
      const std::vector<NodeRef> vertices = GetSequence(polygon);
      if (vertices.size() < 3 ||
          vertices.size() > static_cast<std::size_t>(analytics::kMaxPolygonVertices)) {
        polygon.Fail("a polygon has 3 to " + std::to_string(analytics::kMaxPolygonVertices) +
                     " vertices, not " + std::to_string(vertices.size()));
      }
      for (const NodeRef& v : vertices) r.polygon.push_back(GetPoint(v));
      if (const std::optional<std::string> why = analytics::ValidatePolygon(r.polygon)) {
        polygon.Fail(*why);
      }
      site.regions.push_back(std::move(r));
    }
  }
  if (const std::optional<NodeRef> lines = root.Find("lines")) {
    const std::vector<NodeRef> items = GetSequence(*lines);
    if (items.size() > static_cast<std::size_t>(analytics::kMaxLines)) {
      lines->Fail("more than " + std::to_string(analytics::kMaxLines) + " lines");
    }
    std::set<std::string> names;
    for (const NodeRef& item : items) {
      const MapRef line(item, {"name", "from", "to"});
      analytics::Line l;
      l.name = GetName(line.Get("name"), &names, "line");
      l.from = GetPoint(line.Get("from"));
      l.to = GetPoint(line.Get("to"));
      if (!((l.to - l.from).norm() > 1e-6)) line.Get("to").Fail("the line has no length");
      site.lines.push_back(std::move(l));
    }
  }
  if (site.regions.empty() && site.lines.empty()) {
    root_node.Fail("a site needs at least one region or line");
  }
  if (const std::optional<NodeRef> rules = root.Find("rules")) {
    const MapRef r(*rules, {"hysteresis_m", "hold_s", "max_gap_s"}, /*null_is_empty=*/true);
    analytics::AnalyticsOptions& o = site.options;
    if (auto v = r.Find("hysteresis_m"))
      o.hysteresis_m = GetDouble(*v, DoubleRange::Closed(0, 100));
    if (auto v = r.Find("hold_s")) o.hold_s = GetDouble(*v, DoubleRange::Closed(0, 3600));
    if (auto v = r.Find("max_gap_s")) {
      o.max_gap_s = GetDouble(*v, DoubleRange::LeftOpen(0, 3600));
    }
  }
  if (const std::optional<std::string> why = analytics::ValidateSite(site)) {
    root_node.Fail(*why);  // not reached: each part was checked where it is written
  }
  return site;
}

analytics::Site LoadSiteFile(const std::string& path) {
  return ParseSite(internal::ReadTextFile(path), path);
}

bool LooksLikeSite(std::string_view text) {
  try {
    const YAML::Node root = YAML::Load(std::string(text));
    if (!root.IsMap()) return false;
    const YAML::Node format = root["format"];
    return format.IsScalar() && format.Scalar().rfind("mvtrack.site/", 0) == 0;
  } catch (...) {
    return false;
  }
}

std::string SiteToYaml(const analytics::Site& site) {
  const auto point = [](const Vec2& p) {
    return "[" + internal::FormatDouble(p.x()) + ", " + internal::FormatDouble(p.y()) + "]";
  };
  const auto quoted = [](const std::string& name) {
    YAML::Emitter e;
    e << YAML::DoubleQuoted << name;
    return std::string(e.c_str());
  };
  std::string out = "format: " + std::string(kSiteFormat) + "\n";
  if (!site.regions.empty()) out += "regions:\n";
  for (const analytics::Region& r : site.regions) {
    out += "  - name: " + quoted(r.name) + "\n    polygon: [";
    for (std::size_t i = 0; i < r.polygon.size(); ++i) {
      out += (i > 0 ? ", " : "") + point(r.polygon[i]);
    }
    out += "]\n";
  }
  if (!site.lines.empty()) out += "lines:\n";
  for (const analytics::Line& l : site.lines) {
    out += "  - name: " + quoted(l.name) + "\n    from: " + point(l.from) +
           "\n    to: " + point(l.to) + "\n";
  }
  out += "rules:\n  hysteresis_m: " + internal::FormatDouble(site.options.hysteresis_m) +
         "\n  hold_s: " + internal::FormatDouble(site.options.hold_s) +
         "\n  max_gap_s: " + internal::FormatDouble(site.options.max_gap_s) + "\n";
  return out;
}

}  // namespace mvtrack::config
