#pragma once
/// @file
/// IdReservation: track ids that never repeat across daemon restarts, kill -9 included. The
/// state directory holds one small file, `track_ids`, with the end of a reserved block of ids:
/// a run starts its ids at the stored end and, before giving any out, stores a new end one block
/// further (written to a temporary file, synced, renamed over the old one); while it runs it
/// extends the reservation whenever the next id comes within half a block of its end. A crash
/// therefore never reuses an id; it skips at most one block.

#include <cstdint>
#include <filesystem>
#include <string>

#include "core/types.h"

namespace mvtrack::service {

/// See the file comment. Single-owner; not thread-safe (the daemon's control thread).
class IdReservation {
 public:
  /// The file's first line, then "reserved_end=N".
  static constexpr const char* kFormat = "mvtrack.track_ids/1";

  /// Reads `directory`/track_ids (absent: ids start at 1), reserves [start, start + block) and
  /// stores its end. `block` >= 1. Returns false and sets `why` when the file cannot be read,
  /// is malformed (a truncated or foreign file is refused, not guessed around: the operator
  /// removes it) or cannot be written.
  bool Open(const std::filesystem::path& directory, std::int64_t block, std::string* why);

  /// The first id of this run.
  TrackId3D first_id() const { return first_id_; }
  /// The end (exclusive) of the stored reservation.
  TrackId3D reserved_end() const { return reserved_end_; }

  /// Called with the id the next new track will get: when it is within half a block of the
  /// reservation's end, stores a new end `block` past it. Returns false and sets `why` when the
  /// file cannot be written (the caller logs it; ids stay unique while next_id < reserved_end).
  bool Extend(TrackId3D next_id, std::string* why);

 private:
  bool Store(TrackId3D end, std::string* why);

  std::filesystem::path file_;
  std::int64_t block_ = 0;
  TrackId3D first_id_ = 1;
  TrackId3D reserved_end_ = 1;
};

}  // namespace mvtrack::service
