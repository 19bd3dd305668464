#pragma once
/// @file
/// The site file of the analytics (issue 41): named floor regions and lines, and the rules'
/// parameters, in a small YAML document (docs/FORMATS.md "Site file"):
///
///     format: mvtrack.site/1
///     regions:
///       - name: entrance
///         polygon: [[0.0, 0.0], [2.0, 0.0], [2.0, 1.5], [0.0, 1.5]]   # metres, floor frame
///     lines:
///       - name: door
///         from: [0.0, 1.0]
///         to: [0.0, 3.0]
///     rules:              # optional; these are the defaults
///       hysteresis_m: 0.3
///       hold_s: 0.5
///       max_gap_s: 5.0
///
/// Loading is strict like the rest of lib/config: unknown keys (with a did-you-mean), wrong
/// types, non-finite numbers, a polygon that is not simple, repeated names and out-of-range
/// values are config::ConfigErrors naming the file, line, column and key path.

#include <string>
#include <string_view>

#include "analytics/site_analytics.h"
#include "config/config_error.h"

namespace mvtrack::config {

/// The value of the mandatory top-level `format` key of a site file.
inline constexpr std::string_view kSiteFormat = "mvtrack.site/1";

/// Parses a site document; `source_name` names it in errors.
/// @throws ConfigError
analytics::Site ParseSite(std::string_view text, const std::string& source_name);

/// Reads and parses a site file.
/// @throws ConfigError
analytics::Site LoadSiteFile(const std::string& path);

/// True when `text` is a YAML map whose `format` starts with "mvtrack.site/" (how `mvtrack
/// check-config` recognises a site file).
bool LooksLikeSite(std::string_view text);

/// The canonical YAML of `site` (every rule written out), parsable by ParseSite.
std::string SiteToYaml(const analytics::Site& site);

}  // namespace mvtrack::config
