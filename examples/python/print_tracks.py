#!/usr/bin/env python3
"""Prints the tracks mvtrackd publishes, live.

  print_tracks.py                         LCM's default URL ($LCM_DEFAULT_URL, else udpm)
  print_tracks.py --url 'udpm://239.255.76.67:7667?ttl=0'
  print_tracks.py --url 'file:///tmp/tracks.lcmlog?speed=1'     a recording, played as if live
  print_tracks.py --json --count 100      100 messages as JSON lines, then exit

Subscribes to MVTRACK_TRACKS (tracks3d_t) and prints every message; --status also prints
MVTRACK_STATUS (tracker_status_t). Messages that do not decode are reported on stderr and
skipped. Needs PyPI's `lcm` and the generated types (docs/PYTHON.md). Exit status: 0 (Ctrl-C,
--count reached, or the end of a file:// log), 1 when --timeout passes without a message or LCM
cannot start, 2 on usage errors.
"""
import argparse
import json
import sys

import lcm

from mvtrack_msgs import (STATUS_CHANNEL, TRACKS_CHANNEL, decode, format_tracks, listen,
                          tracks_to_dict)
import mvtrack


def main():
    ap = argparse.ArgumentParser(description="Print mvtrack tracks live.")
    ap.add_argument("--url", default=None, help="LCM URL (default: LCM's default)")
    ap.add_argument("--channel", default=TRACKS_CHANNEL, help="tracks channel")
    ap.add_argument("--status", action="store_true", help="also print " + STATUS_CHANNEL)
    ap.add_argument("--json", action="store_true", help="one JSON line per tracks message")
    ap.add_argument("--count", type=int, default=0, help="exit after N tracks messages (0: never)")
    ap.add_argument("--timeout", type=float, default=0.0,
                    help="exit with status 1 after this many seconds without a message (0: never)")
    a = ap.parse_args()
    if a.count < 0 or a.timeout < 0:
        ap.error("--count and --timeout must be >= 0")

    try:
        lc = lcm.LCM(a.url) if a.url else lcm.LCM()
    except (RuntimeError, OSError) as e:
        print(f"print_tracks.py: cannot start LCM ({a.url or 'default URL'}): {e}", file=sys.stderr)
        return 1
    received = [0]

    def on_tracks(channel, data):
        try:
            msg = decode(data)
        except ValueError as e:
            print(f"print_tracks.py: {channel}: {e}", file=sys.stderr)
            return
        if not isinstance(msg, mvtrack.tracks3d_t):
            print(f"print_tracks.py: {channel}: not a tracks3d_t message", file=sys.stderr)
            return
        received[0] += 1
        print(json.dumps(tracks_to_dict(msg)) if a.json else "\n".join(format_tracks(msg)),
              flush=True)

    def on_status(channel, data):
        try:
            s = decode(data)
        except ValueError as e:
            print(f"print_tracks.py: {channel}: {e}", file=sys.stderr)
            return
        if isinstance(s, mvtrack.tracker_status_t):
            print(f"status: frame {s.last_frame}, {s.confirmed_tracks} confirmed / "
                  f"{s.active_tracks} active, latency p50 {s.latency_p50_us / 1000:.1f} ms "
                  f"p99 {s.latency_p99_us / 1000:.1f} ms, flags {s.flags}", flush=True)

    lc.subscribe(a.channel, on_tracks)
    if a.status:
        lc.subscribe(STATUS_CHANNEL, on_status)
    return listen(lc, "print_tracks.py", a.channel, received, a.count, a.timeout)


if __name__ == "__main__":
    sys.exit(main())
