#pragma once
/// @file
/// Strict YAML helpers shared by lib/config and the daemon's config (internal API: includes
/// yaml-cpp, so only .cc files of runtime modules may include it; link `yaml-cpp` yourself).
///
/// Every helper either returns a value that passed its checks or throws config::ConfigError
/// naming the file, the 1-based line and column, the dotted key path and the reason. Scalars are
/// parsed by these helpers, not by yaml-cpp's `as<T>()`: numbers must be plain (unquoted)
/// scalars in decimal notation, finite, and within range; integers have no fraction or exponent;
/// booleans are `true` or `false` (any case form YAML 1.2 allows), never `yes`/`on`/`1`.
/// Stateless functions and small immutable value types; thread-compatible.

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "config/config_error.h"
#include "core/suggest.h"

namespace mvtrack::config::internal {

/// Largest image side a calibration file may give, pixels (a bound on untrusted input).
inline constexpr int kMaxImageSidePx = 1 << 20;

/// A YAML node together with its source file, its key path and its position, so that any
/// problem with it can be reported precisely. Cheap to copy (YAML::Node is a handle). Not
/// assignable: YAML::Node's operator= writes through to the node it refers to (yaml-cpp's
/// reference semantics, so assigning would edit the document) and can throw.
class NodeRef {
 public:
  /// `line`/`column` are 1-based, 0 when unknown.
  NodeRef(const YAML::Node& node, std::string file, std::string path, int line, int column);
  NodeRef(const NodeRef&) = default;
  NodeRef(NodeRef&&) = default;
  NodeRef& operator=(const NodeRef&) = delete;
  NodeRef& operator=(NodeRef&&) = delete;
  ~NodeRef() = default;

  /// The document root of `file` (position taken from the node's mark, key path `path`).
  static NodeRef Root(const YAML::Node& node, std::string file, std::string path = {});

  const YAML::Node& node() const { return node_; }
  const std::string& file() const { return file_; }
  /// Dotted key path, e.g. "tracker.association.lambda" or "cameras[1].K[0]".
  const std::string& path() const { return path_; }
  int line() const { return line_; }
  int column() const { return column_; }

  /// True for a null node (`key:` with nothing after it, `~`, `null`) or an absent document.
  bool IsNull() const;
  /// The key path of child `key` of this map.
  std::string ChildPath(std::string_view key) const;
  /// The key path of element `index` of this sequence.
  std::string ElementPath(std::size_t index) const;

  /// The error for this node (its file, position and key path).
  ConfigError Error(const std::string& reason) const;
  /// Throws Error(reason).
  [[noreturn]] void Fail(const std::string& reason) const;

 private:
  YAML::Node node_;
  std::string file_;
  std::string path_;
  int line_ = 0;
  int column_ = 0;
};

/// A known key that belongs elsewhere: when an unknown key equals `key` (or is a likely typo
/// of it), the error reads "unknown key (did you mean <suggestion>?)"; `suggestion` carries its
/// own quotes, e.g. "'tracker.association.lambda'" or "'a.min_hits' or 'b.min_hits'".
struct KeyHint {
  std::string key;
  std::string suggestion;
};

/// A strict view of a YAML map. Construction checks that the node is a map (or null, when
/// `null_is_empty`: `sort:` with every entry commented out means "all defaults"), that every key
/// is a scalar, that no key appears twice, and that every key is in `allowed`. An unknown key is
/// reported at the key's position with a did-you-mean suggestion: a hint whose key equals it,
/// else the closest allowed key (SuggestClosest), else the closest hint key, else the list of
/// allowed keys.
class MapRef {
 public:
  MapRef(const NodeRef& node,
         std::vector<std::string> allowed,
         bool null_is_empty = false,
         const std::vector<KeyHint>& hints = {});

  /// The map itself.
  const NodeRef& ref() const { return ref_; }
  /// The keys present, in document order.
  std::vector<std::string> keys() const;
  /// Whether `key` is present.
  bool Has(std::string_view key) const;
  /// The value of `key`, or nullopt when absent. A null value is reported at its key's position.
  std::optional<NodeRef> Find(std::string_view key) const;
  /// The value of a required key; throws "missing required key '<key>'" at the map otherwise.
  NodeRef Get(std::string_view key) const;
  /// Position of `key` itself (for errors about the key rather than its value); the map's
  /// position when absent.
  NodeRef KeyRef(std::string_view key) const;
  /// Of `keys`, returns the single one present; throws when none or several are present.
  /// `what` names the alternatives in the message (e.g. "rotation").
  std::string RequireExactlyOne(std::initializer_list<std::string_view> keys,
                                std::string_view what) const;

 private:
  struct Entry {
    std::string key;
    NodeRef key_ref;
    NodeRef value;
  };
  const Entry* FindEntry(std::string_view key) const;

  NodeRef ref_;
  std::vector<Entry> entries_;
};

/// Checks that `node` is a map with distinct scalar keys, all in `allowed` (see MapRef).
void RequireOnlyKeys(const NodeRef& node,
                     const std::vector<std::string>& allowed,
                     const std::vector<KeyHint>& hints = {});

/// An interval of allowed real values; both ends inclusive unless marked open.
struct DoubleRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;
  bool max_open = false;

  /// Any finite value.
  static DoubleRange Any() { return {}; }
  /// [lo, +inf).
  static DoubleRange AtLeast(double lo) { return {lo, std::numeric_limits<double>::infinity()}; }
  /// (lo, +inf).
  static DoubleRange GreaterThan(double lo) {
    return {lo, std::numeric_limits<double>::infinity(), true, false};
  }
  /// [lo, hi].
  static DoubleRange Closed(double lo, double hi) { return {lo, hi}; }
  /// (lo, hi].
  static DoubleRange LeftOpen(double lo, double hi) { return {lo, hi, true, false}; }

  bool Contains(double value) const;
  /// E.g. "must be in [0, 1]", "must be > 0", "must be >= 1".
  std::string Describe() const;
};

/// A finite real number within `range`. Accepts plain decimal scalars ("1", "-2.5", "1e-3",
/// ".5", "+3"); rejects quoted strings, null, maps, sequences, words, `.nan`/`.inf` and values
/// that overflow a double.
double GetDouble(const NodeRef& node, const DoubleRange& range = DoubleRange::Any());
/// A decimal integer in [min, max] (no fraction, no exponent, no quotes).
std::int64_t GetInt64(const NodeRef& node,
                      std::int64_t min = std::numeric_limits<std::int64_t>::min(),
                      std::int64_t max = std::numeric_limits<std::int64_t>::max());
/// A decimal integer in [min, max] that fits an int.
int GetInt(const NodeRef& node,
           int min = std::numeric_limits<int>::min(),
           int max = std::numeric_limits<int>::max());
/// `true`/`True`/`TRUE` or `false`/`False`/`FALSE` (plain scalar).
bool GetBool(const NodeRef& node);
/// Any non-null scalar (plain or quoted) as text; empty text only when `allow_empty`.
std::string GetString(const NodeRef& node, bool allow_empty = false);

/// A name mapped to an enum value by `from_name` (e.g. association::ClusteringMethodFromName).
/// `names` lists the accepted names for the message and the did-you-mean suggestion.
template <typename Enum, typename FromName>
Enum GetEnum(const NodeRef& node, FromName from_name, const std::vector<std::string>& names);

/// The elements of a sequence, each with its key path ("path[i]") and position; when
/// `expected_size` is set, any other length is an error.
std::vector<NodeRef> GetSequence(const NodeRef& node,
                                 std::optional<std::size_t> expected_size = std::nullopt);

/// See core/suggest.h (kept here under these names for lib/config's callers).
using core::EditDistance;
using core::SuggestClosest;

/// Parses one YAML document (JSON is valid YAML). A syntax error is a ConfigError with the line
/// and column of the problem; so is a stream with more than one document. An empty document
/// (empty text or only comments) yields a null root node; callers decide whether that is valid.
NodeRef ParseDocument(std::string_view text, const std::string& source_name);
/// Reads a whole file as text; ConfigError naming the file when it does not exist, is not a
/// regular file or cannot be read.
std::string ReadTextFile(const std::string& path);
/// Writes `text` to `path` through a temporary file in the same directory and a rename, so a
/// reader never sees a partial file; ConfigError naming the file on failure.
void WriteTextFile(const std::string& path, std::string_view text);

/// Shortest decimal text that parses back to exactly `value` (std::to_chars), with ".0"
/// appended to integral values so they read as reals; ".nan", ".inf", "-.inf" for non-finite.
std::string FormatDouble(double value);
/// `text` as a YAML double-quoted scalar (escapes '"', '\\' and control characters).
std::string QuoteString(std::string_view text);
/// Joins names as "'a', 'b', 'c'".
std::string QuoteList(const std::vector<std::string>& names);

// ------------------------------------------------------------------------------------------------

template <typename Enum, typename FromName>
Enum GetEnum(const NodeRef& node, FromName from_name, const std::vector<std::string>& names) {
  const std::string text = GetString(node);
  const std::optional<Enum> value = from_name(std::string_view(text));
  if (value.has_value()) return *value;
  std::string reason = "unknown value '" + text + "'";
  if (const std::optional<std::string> close = SuggestClosest(text, names)) {
    reason += " (did you mean '" + *close + "'?)";
  } else {
    reason += " (expected one of " + QuoteList(names) + ")";
  }
  node.Fail(reason);
}

}  // namespace mvtrack::config::internal
