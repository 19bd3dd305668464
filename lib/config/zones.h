#pragma once
/// @file
/// Zones of a site (issue 43, first part): the cameras of a large rig split into zones of
/// cameras whose views share the floor, one tracker (mvtrackd) per zone. Each zone tracks with
/// its own cameras ("core") plus the cameras of other zones that see its floor ("border"), so
/// the floor along a border is triangulated by both neighbouring zones from the same cameras'
/// detections (multicast delivers a border camera to both), which is what a stitcher needs to
/// join the zones' tracks into one id space. Pure computation (no I/O), deterministic.
///
/// The split (PartitionZones): every camera's coverage is the set of cells of a floor grid whose
/// centre at sample_height_m it sees (geometry::SeesPoint, as `mvtrack calib check` samples);
/// its position for the split is the mean of those cells (its centre, when it sees none). The
/// cameras are split recursively along the longer extent of their positions, ties by camera id,
/// into ⌈n / max_cameras⌉ parts of nearly equal size, so zones are compact floor areas of at
/// most max_cameras cameras. Then a camera of another zone is a border camera of zone Z when it
/// sees at least min_shared_area_m2 of the floor Z's own cameras see.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "config/calibration_check.h"
#include "core/types.h"
#include "geometry/camera_model.h"

namespace mvtrack::config {

/// Options of PartitionZones.
struct ZoneOptions {
  /// Largest number of a zone's own cameras, >= 2 (border cameras come on top).
  int max_cameras = 16;
  /// Side of the floor grid cells, metres, > 0.
  double cell_m = 0.5;
  /// Height of the sampled points above the floor, metres (a standing person's torso).
  double sample_height_m = 1.0;
  /// Floor a camera of another zone must share with a zone's cameras to be its border camera,
  /// m², >= 0.
  double min_shared_area_m2 = 2.0;
  /// Checks the ranges above; on failure writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// One zone.
struct Zone {
  std::string name;               ///< "zone1", "zone2", ... in the order of the split
  std::vector<CameraId> cameras;  ///< its own cameras, ascending
  /// Cameras of other zones that see its floor (tracked by it too), ascending.
  std::vector<CameraId> border;
  /// The zones its border cameras belong to, and the zones whose border it is part of, by name.
  std::vector<std::string> neighbours;
  /// Floor its own cameras see, m² (cells seen at sample height).
  double area_m2 = 0.0;
  /// Of it, seen by a border camera too: the floor it shares with its neighbours, m².
  double border_area_m2 = 0.0;
  /// Bounding box of the floor its own cameras see (its cameras' centres when they see none).
  FloorRegion bounds;
  /// The zone daemon's configuration file (relative to the zones file), when known.
  std::string daemon;
};

/// Most zones of a site (the stitched output's zone indices are int16; the decoders' limit,
/// transport::DecodeLimits::max_zones, and stitch::Stitcher's).
inline constexpr int kMaxZones = 256;

/// The `format` of a zones file.
inline constexpr std::string_view kZonesFormat = "mvtrack.zones/1";

/// Why `name` cannot name a zone (1 to 32 characters a-z, 0-9 and _: it names channels), or
/// nullopt when it can.
std::optional<std::string> ValidateZoneName(std::string_view name);

/// Parses a zones file (what `mvtrack calib zones --out` writes as zones.yaml, or written by
/// hand; docs/FORMATS.md "Zones"):
///
///     format: mvtrack.zones/1
///     zones:
///       - name: zone1               # ValidateZoneName, unique
///         cameras: [0, 1, 2]        # its own cameras: at least one, no camera in two zones
///         border_cameras: [3]       # optional: other zones' cameras it tracks with too
///         neighbours: [zone2]       # optional: names of zones of the file
///         daemon: zone1.yaml        # optional: its daemon configuration
///
/// Strict like every configuration file: a ConfigError with file, line and column on unknown
/// keys, wrong types, duplicate names or cameras. Only name, cameras, border, neighbours and
/// daemon of the zones are set.
std::vector<Zone> ParseZones(std::string_view text, const std::string& source_name);
/// ParseZones of a file's text.
std::vector<Zone> LoadZonesFile(const std::string& path);
/// The zones file of `zones` (valid), with `comment` (lines without '#', may be empty) on top.
/// ParseZones reads it back.
std::string ZonesToYaml(const std::vector<Zone>& zones, const std::string& comment);

/// Splits `cameras` (valid, at least 2; checked) into zones; see the file comment. One zone
/// when there are at most max_cameras cameras. `options` must be valid (checked).
std::vector<Zone> PartitionZones(const std::vector<geometry::CameraModel>& cameras,
                                 const ZoneOptions& options = {});

/// The names of `zones`, in order.
std::vector<std::string> ZoneNames(const std::vector<Zone>& zones);

/// The channel of zone `zone` for a site channel: "<channel>_<ZONE>" (the zone name in upper
/// case), e.g. MVTRACK_TRACKS_ZONE1.
std::string ZoneChannel(const std::string& channel, const std::string& zone);

}  // namespace mvtrack::config
