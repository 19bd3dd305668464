#pragma once
/// @file
/// JSON documents to build and write: nlohmann-json's trees under the project's names, and the
/// one way they are written (Dump). For writers whose output is a tree of values (the web
/// events, `mvtrack bench`'s results.json); canonical writers that fix every byte (the tracks
/// JSONL, the eval report) format numbers themselves and quote with json::Quote (json.h).
/// Including this header brings in nlohmann/json.hpp (heavy: include it only in .cc files).

#include <nlohmann/json.hpp>
#include <string>

namespace mvtrack::json {

/// A document whose objects keep their keys sorted (deterministic output whatever the order of
/// insertion).
using Document = nlohmann::json;
/// A document whose objects keep their keys in insertion order (for files people read).
using OrderedDocument = nlohmann::ordered_json;

/// How Dump writes text outside ASCII.
enum class Ascii {
  kKeep,    ///< UTF-8 as is
  kEscape,  ///< every non-ASCII code point as \uXXXX (above U+FFFF a surrogate pair), so the text
            ///< is pure ASCII
};

/// `doc` as text: on one line when `indent` < 0, else pretty-printed with `indent` spaces;
/// invalid UTF-8 in strings is replaced by U+FFFD (never an exception); NaN and infinities are
/// written as null.
std::string Dump(const Document& doc, int indent = -1, Ascii ascii = Ascii::kKeep);
/// The same for an ordered document.
std::string Dump(const OrderedDocument& doc, int indent = -1, Ascii ascii = Ascii::kKeep);

}  // namespace mvtrack::json
