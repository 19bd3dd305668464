#pragma once
/// @file
/// Internal: the calibration parser working on an already parsed YAML node, so that a larger
/// file (e.g. the daemon config) can embed a calibration map. Includes yaml-cpp.

#include "config/calibration.h"
#include "config/internal/yaml_node.h"

namespace mvtrack::config::internal {

/// Parses a `mvtrack.calibration/1` map (see docs/FORMATS.md); key paths in errors start at
/// `root.path()`. A null node is an error ("empty calibration").
/// @throws ConfigError on any content error.
CalibrationDocument ParseCalibrationNode(const NodeRef& root);

}  // namespace mvtrack::config::internal
