"""Shared helpers of the mvtrack Python examples: decoding by fingerprint and printing tracks.

Needs the generated types (`pip install mvtrack_lcmtypes-*.whl`, or PYTHONPATH=<build>/lcmtypes/
python) and nothing else; the examples that talk to LCM also need PyPI's `lcm`.
"""
import math

import mvtrack

# Channels published by mvtrackd (lib/transport/channels.h).
TRACKS_CHANNEL = "MVTRACK_TRACKS"
STATUS_CHANNEL = "MVTRACK_STATUS"
DETECTIONS_PREFIX = "MVTRACK_DETECTIONS"

# Every top-level message type, by the 8-byte fingerprint that starts its encoding.
TYPES = {t._get_packed_fingerprint(): t
         for t in (mvtrack.tracks3d_t, mvtrack.camera_detections_t, mvtrack.tracker_status_t)}

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
