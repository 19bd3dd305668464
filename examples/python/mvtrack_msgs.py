"""Shared helpers of the mvtrack Python examples: decoding by fingerprint, printing tracks and
site analytics (events and counts).

Needs the generated types (`pip install mvtrack_lcmtypes-*.whl`, or PYTHONPATH=<build>/lcmtypes/
python) and nothing else; the examples that talk to LCM also need PyPI's `lcm`.
"""
import math
import signal
import sys

import mvtrack

# Channels published by mvtrackd (lib/transport/channels.h).
TRACKS_CHANNEL = "MVTRACK_TRACKS"
STATUS_CHANNEL = "MVTRACK_STATUS"
DETECTIONS_PREFIX = "MVTRACK_DETECTIONS"
EVENTS_CHANNEL = "MVTRACK_ANALYTICS_EVENTS"  # analytics_event_t (daemon key analytics.events_channel)
COUNTS_CHANNEL = "MVTRACK_SITE_COUNTS"       # site_counts_t (analytics.counts_channel)

# Every top-level message type, by the 8-byte fingerprint that starts its encoding.
TYPES = {t._get_packed_fingerprint(): t
         for t in (mvtrack.tracks3d_t, mvtrack.camera_detections_t, mvtrack.tracker_status_t,
                   mvtrack.analytics_event_t, mvtrack.site_counts_t)}

STATE_NAMES = {mvtrack.track3d_t.STATE_TENTATIVE: "tentative",
               mvtrack.track3d_t.STATE_CONFIRMED: "confirmed",
               mvtrack.track3d_t.STATE_LOST: "lost",
               mvtrack.track3d_t.STATE_ENDED: "ended"}


def decode(data):
    """The message in `data` (any mvtrack top-level type), or None for another type. Raises
    ValueError when the bytes carry a known fingerprint but do not decode."""
    cls = TYPES.get(bytes(data[:8]))
    if cls is None:
        return None
    try:
        return cls.decode(data)
    except Exception as e:  # the generated decoder raises struct.error, ValueError, ...
        raise ValueError(f"{cls.__name__}: {e}") from e


def point(p):
    """[x, y, z], or None when a coordinate is not finite (JSON has no NaN)."""
    return list(p) if all(math.isfinite(v) for v in p) else None


def track_to_dict(t):
    """A track3d_t as a plain dict (JSON-ready; invalid joints are None)."""
    return {"id": t.id, "state": STATE_NAMES.get(t.state, str(t.state)),
            "position": point(t.position), "confidence": t.confidence,
            "age_frames": t.age_frames, "missed_frames": t.missed_frames,
            "cameras": list(t.camera_ids),
            "joints": [point(j.position) if j.valid else None for j in t.joints]}


def tracks_to_dict(msg):
    """A tracks3d_t as a plain dict (JSON-ready)."""
    return {"utime": msg.utime, "frame": msg.frame, "publish_utime": msg.publish_utime,
            "latency_us": msg.latency_us, "layout": msg.keypoint_layout,
            "tracks": [track_to_dict(t) for t in msg.tracks]}


def format_tracks(msg):
    """Human-readable lines for one tracks3d_t."""
    lines = [f"frame {msg.frame} utime {msg.utime}: {msg.num_tracks} track(s)"
             + (f", latency {msg.latency_us / 1000:.1f} ms" if msg.latency_us else "")]
    for t in msg.tracks:
        x, y, z = t.position
        joints = sum(1 for j in t.joints if j.valid)
        lines.append(f"  id {t.id:4d} {STATE_NAMES.get(t.state, t.state):9s} "
                     f"({x:7.3f}, {y:7.3f}, {z:6.3f}) m  conf {t.confidence:.2f}  "
                     f"cameras {list(t.camera_ids)}"
                     + (f"  joints {joints}/{t.num_joints} ({msg.keypoint_layout})"
                        if t.num_joints else ""))
    return lines


EVENT_KINDS = {mvtrack.analytics_event_t.KIND_ENTER: "enter",
               mvtrack.analytics_event_t.KIND_EXIT: "exit",
               mvtrack.analytics_event_t.KIND_CROSSING: "crossing"}
DIRECTIONS = {mvtrack.analytics_event_t.DIRECTION_LEFT_TO_RIGHT: "left_to_right",
              mvtrack.analytics_event_t.DIRECTION_RIGHT_TO_LEFT: "right_to_left"}


def event_to_dict(e):
    """An analytics_event_t as a plain dict: enter/exit of a region (exit: with the visit's
    enter_utime and dwell) or a crossing of a line (with its direction)."""
    kind = EVENT_KINDS.get(e.kind, str(e.kind))
    d = {"utime": e.utime, "publish_utime": e.publish_utime, "kind": kind, "name": e.name,
         "track_id": e.track_id, "track_ended": bool(e.track_ended)}
    if kind == "exit":
        d["enter_utime"] = e.enter_utime
        d["dwell_s"] = (e.utime - e.enter_utime) / 1e6
    if kind == "crossing":
        d["direction"] = DIRECTIONS.get(e.direction, str(e.direction))
    return d


def format_event(e):
    """One human-readable line for an analytics_event_t."""
    d = event_to_dict(e)
    text = f"{d['utime'] / 1e6:.3f} track {d['track_id']}: {d['kind']} {d['name']}"
    if "dwell_s" in d:
        text += f" after {d['dwell_s']:.1f} s"
    if "direction" in d:
        text += f" {d['direction']}"
    return text + (" (track ended)" if d["track_ended"] else "")


def counts_to_dict(c):
    """A site_counts_t as a plain dict: per region occupancy, entries and exits since the daemon
    started; per line the crossings in each direction."""
    return {"utime": c.utime, "publish_utime": c.publish_utime,
            "regions": {n: {"occupancy": c.occupancy[i], "entries": c.entries[i],
                            "exits": c.exits[i]} for i, n in enumerate(c.region_names)},
            "lines": {n: {"left_to_right": c.left_to_right[i],
                          "right_to_left": c.right_to_left[i]}
                      for i, n in enumerate(c.line_names)}}


def format_counts(c):
    """Human-readable lines for one site_counts_t."""
    lines = [f"counts at {c.utime / 1e6:.3f}:"]
    for i, n in enumerate(c.region_names):
        lines.append(f"  region {n}: {c.occupancy[i]} inside, {c.entries[i]} entries, "
                     f"{c.exits[i]} exits")
    for i, n in enumerate(c.line_names):
        lines.append(f"  line {n}: {c.left_to_right[i]} left_to_right, "
                     f"{c.right_to_left[i]} right_to_left")
    return lines


def listen(lc, program, channel, received, count, timeout, what=""):
    """Handles `lc`'s messages until `received[0]` reaches `count` (0: never), Ctrl-C, the end of
    a file:// log (all: 0) or `timeout` seconds without a message (0: never; 1, with a line on
    stderr naming `what`). Says on stderr that it listens on `channel` first."""
    signal.signal(signal.SIGINT, lambda *_: sys.exit(0))
    print(f"{program}: listening on {channel}", file=sys.stderr, flush=True)
    idle = 0.0
    step = 0.1
    while count == 0 or received[0] < count:
        try:
            handled = lc.handle_timeout(int(step * 1000))
        except (IOError, OSError):
            return 0  # the end of a file:// log
        if handled > 0:
            idle = 0.0
            continue
        idle += step
        if timeout and idle >= timeout:
            got = " ".join(x for x in (str(received[0]), what, "received") if x)
            print(f"{program}: no message for {timeout} s ({got})", file=sys.stderr)
            return 1
    return 0
