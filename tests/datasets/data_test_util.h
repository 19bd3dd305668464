#pragma once
/// @file
/// Helpers of the [data] tests: the data root, the skip-or-fail rule for missing datasets, a
/// cache of loaded datasets (each is loaded once per test binary), and temporary directories.
///
/// Skip rule: a dataset folder missing under the data root (DefaultDataRoot(): $MVTRACK_DATA
/// or ../shared/data next to the repository) FAILs the test when the environment variable CI is
/// set, and otherwise WARNs "SKIPPED: ..." and returns from the test (Catch2 v2 has no SKIP).

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <system_error>

#include "datasets/campus.h"
#include "datasets/dataset.h"
#include "datasets/panoptic.h"
#include "datasets/shelf.h"
#include "datasets/wildtrack.h"

namespace mvtrack::datasets::testing {

/// The data root if `<root>/<folder>` exists; otherwise std::nullopt after FAIL (CI set) or
/// WARN (not set).
inline std::optional<std::filesystem::path> FindDataset(const std::string& folder) {
  const std::filesystem::path root = DefaultDataRoot();
  std::error_code ec;
  if (std::filesystem::is_directory(root / folder, ec)) return root;
  const char* ci = std::getenv("CI");
  const std::string message = "dataset '" + folder + "' not found under " + root.string() +
                              " (set MVTRACK_DATA to the data root)";
  if (ci != nullptr && ci[0] != '\0') {
    FAIL("CI is set and " << message);
  }
  WARN("SKIPPED: " << message);
  return std::nullopt;
}

/// Declares `const std::filesystem::path& root` for dataset `folder`, or leaves the test (see
/// FindDataset).
#define MVTRACK_REQUIRE_DATASET(root, folder)               \
  const std::optional<std::filesystem::path> root##_found = \
      ::mvtrack::datasets::testing::FindDataset(folder);    \
  if (!root##_found.has_value()) return;                    \
  [[maybe_unused]] const std::filesystem::path& root = *root##_found

/// Loaded datasets, keyed by a description of the options, loaded once per test binary.
inline const Dataset& CachedDataset(const std::string& key, Dataset (*load)()) {
  static std::map<std::string, Dataset> cache;
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, load()).first;
  return it->second;
}

inline const Dataset& ShelfData() {
  return CachedDataset("shelf", [] { return LoadShelf(DefaultDataRoot()); });
}
inline const Dataset& CampusClean() {
  return CachedDataset("campus/clean", [] {
    CampusOptions options;
    options.corruption = CorruptionOptions::Clean();
    return LoadCampus(DefaultDataRoot(), options);
  });
}
inline const Dataset& CampusDefault() {
  return CachedDataset("campus/default", [] { return LoadCampus(DefaultDataRoot()); });
}

/// A fresh empty directory under the system temp directory (removed by the destructor).
class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "mvtrack_datasets_XXXXXX").string();
    char* made = mkdtemp(pattern.data());
    REQUIRE(made != nullptr);
    path_ = made;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }

  /// Writes `text` to `<dir>/<relative>`, creating parent directories.
  void Write(const std::string& relative, const std::string& text) const {
    const std::filesystem::path file = path_ / relative;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream out(file, std::ios::binary);
    out << text;
    REQUIRE(out.good());
  }

 private:
  std::filesystem::path path_;
};

}  // namespace mvtrack::datasets::testing
