#!/usr/bin/env python3
"""Reads a recorded mvtrack LCM log (e.g. `mvtrack replay --out tracks.lcmlog`, or lcm-logger
on a live system) and prints or summarises it.

  read_log.py LOG                     summary: events per channel, frames, tracks (first/last
                                      frame, frames seen, mean position), detections per camera,
                                      the last tracker status
  read_log.py --print LOG             also every tracks message, human-readable
  read_log.py --json LOG              every tracks message as one JSON line on stdout (nothing
                                      else there; the summary goes to stderr)

Needs PyPI's `lcm` (lcm.EventLog) and the generated types (pip install the mvtrack-lcmtypes
wheel; see docs/PYTHON.md). Exit status: 0 read, 1 unreadable log or undecodable message.
"""
import argparse
import json
import sys
from collections import Counter, defaultdict

import lcm

from mvtrack_msgs import (DETECTIONS_PREFIX, STATUS_CHANNEL, TRACKS_CHANNEL, decode,
                          format_tracks, tracks_to_dict)
import mvtrack


def main():
    ap = argparse.ArgumentParser(description="Print or summarise an mvtrack LCM log.")
    ap.add_argument("log", help="LCM log file")
    group = ap.add_mutually_exclusive_group()
    group.add_argument("--print", action="store_true", help="print every tracks message")
    group.add_argument("--json", action="store_true",
                       help="every tracks message as a JSON line on stdout")
    a = ap.parse_args()

    try:
        log = lcm.EventLog(a.log, "r")
    except (IOError, OSError, ValueError) as e:
        print(f"read_log.py: cannot open {a.log}: {e}", file=sys.stderr)
        return 1
    summary_out = sys.stderr if a.json else sys.stdout

    per_channel = Counter()
    other = Counter()
    frames = 0
    tracks = {}  # id -> [first frame, last frame, frames seen, sum x, sum y, sum z]
    detections = defaultdict(lambda: [0, 0])  # camera -> [camera-frames, detections]
    status = None
    for event in log:
        per_channel[event.channel] += 1
        try:
            msg = decode(event.data)
        except ValueError as e:
            print(f"read_log.py: {a.log}: event {event.eventnum} on {event.channel}: {e}",
                  file=sys.stderr)
            return 1
        if msg is None:
            other[event.channel] += 1
        elif isinstance(msg, mvtrack.tracks3d_t):
            frames += 1
            for t in msg.tracks:
                s = tracks.setdefault(t.id, [msg.frame, msg.frame, 0, 0.0, 0.0, 0.0])
                s[1] = msg.frame
                s[2] += 1
                for k in range(3):
                    s[3 + k] += t.position[k]
            if a.json:
                print(json.dumps(tracks_to_dict(msg)))
            elif a.print:
                print("\n".join(format_tracks(msg)))
        elif isinstance(msg, mvtrack.camera_detections_t):
            detections[msg.camera_id][0] += 1
            detections[msg.camera_id][1] += msg.num_detections
        elif isinstance(msg, mvtrack.tracker_status_t):
            status = msg

    def out(line):
        print(line, file=summary_out)

    out(f"{a.log}: {sum(per_channel.values())} events")
    for channel, n in sorted(per_channel.items()):
        out(f"  {channel}: {n}" + (" (not an mvtrack type)" if other[channel] else ""))
    if frames:
        out(f"tracks: {frames} frame(s), {len(tracks)} track id(s)")
        for tid, (first, last, seen, sx, sy, sz) in sorted(tracks.items()):
            out(f"  id {tid:4d}: frames {first}-{last} ({seen} seen), mean position "
                f"({sx / seen:.3f}, {sy / seen:.3f}, {sz / seen:.3f}) m")
    if detections:
        out(f"detections: {len(detections)} camera(s)")
        for camera, (n, d) in sorted(detections.items()):
            out(f"  camera {camera}: {n} camera-frame(s), {d} detection(s)")
    if status is not None:
        out(f"last status: version {status.version}, frame {status.last_frame}, "
            f"{status.confirmed_tracks} confirmed / {status.active_tracks} active track(s), "
            f"latency p50 {status.latency_p50_us / 1000:.1f} ms, flags {status.flags}")
    if not any(ch == TRACKS_CHANNEL or ch == STATUS_CHANNEL or ch.startswith(DETECTIONS_PREFIX)
               for ch in per_channel):
        out("no mvtrack channel in this log")
    return 0


if __name__ == "__main__":
    sys.exit(main())
