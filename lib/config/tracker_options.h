#pragma once
/// @file
/// Tracker options in YAML: a document whose top-level key `tracker:` holds
/// tracker::TrackerOptions, with the sub-maps `sort`, `association`, `triangulation` and
/// `linking` (docs/FORMATS.md, "Tracker options (YAML)"; every key is documented in
/// docs/examples/tracker_options.yaml).
///
/// Every key is optional; an absent key keeps its default (the paper's values). Unknown keys
/// (with a did-you-mean suggestion), wrong types, non-finite or out-of-range values and options
/// rejected by TrackerOptions::Validate are ConfigErrors naming the file, line and key path.
/// Stateless functions; thread-compatible.

#include <optional>
#include <string>
#include <string_view>

#include "config/config_error.h"
#include "tracker/options.h"

namespace mvtrack::config {

/// Parses a tracker options document; `source_name` (usually the path) is used in errors.
/// @throws ConfigError on any syntax or content error (an empty document included).
tracker::TrackerOptions ParseTrackerOptions(std::string_view text, const std::string& source_name);

/// Reads and parses the tracker options file at `path`.
/// @throws ConfigError when the file is missing or unreadable, or on any content error.
tracker::TrackerOptions LoadTrackerOptionsFile(const std::string& path);

/// The effective options as a canonical document ("tracker:" followed by every option, in a
/// fixed order, reals in their shortest exact form): ParseTrackerOptions(TrackerOptionsToYaml(o))
/// reproduces `o` exactly, and equal options give identical text (the daemon logs it and
/// hashes it to identify its configuration).
std::string TrackerOptionsToYaml(const tracker::TrackerOptions& options);

/// "boxes" or "poses" (the `tracker.mode` names).
std::string_view InputModeName(tracker::InputMode mode);
/// Inverse of InputModeName; nullopt for an unknown name.
std::optional<tracker::InputMode> InputModeFromName(std::string_view name);
/// "center", "bottom_center" or "center_ends" (the `tracker.box_point` names).
std::string_view BoxPointName(tracker::BoxPoint point);
/// Inverse of BoxPointName; nullopt for an unknown name.
std::optional<tracker::BoxPoint> BoxPointFromName(std::string_view name);

}  // namespace mvtrack::config
