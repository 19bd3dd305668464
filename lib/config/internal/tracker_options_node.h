#pragma once
/// @file
/// Internal: the tracker options parser and writer working on YAML nodes, so that a larger file
/// (the daemon config) can embed the same `tracker:` map. Includes yaml-cpp.

#include <string>

#include "config/internal/yaml_node.h"
#include "tracker/options.h"

namespace mvtrack::config::internal {

/// Maps the `tracker:` map `node` onto TrackerOptions (defaults for absent keys; null = all
/// defaults) and validates the result; key paths in errors start at `node.path()`.
/// @throws ConfigError on an unknown key, a wrong type, a value out of range, or options that
/// fail TrackerOptions::Validate (reported at the offending key when it can be identified).
tracker::TrackerOptions ParseTrackerOptionsNode(const NodeRef& node);

/// Appends every option as YAML lines "key: value" (sub-maps nested by two more spaces), each
/// line indented by `indent` spaces: the body of a `tracker:` map.
void AppendTrackerOptionsYaml(const tracker::TrackerOptions& options, int indent, std::string* out);

}  // namespace mvtrack::config::internal
