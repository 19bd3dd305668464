#!/usr/bin/env python3
"""Prints mvtrackd's site analytics, live: region entries and exits, line crossings, counts.

  print_site.py                           LCM's default URL ($LCM_DEFAULT_URL, else udpm)
  print_site.py --url 'file:///tmp/out.lcmlog?speed=1'   a recording, played as if live
  print_site.py --json --count 10         10 events as JSON lines, then exit
  print_site.py --counts                  also the periodic counts (site_counts_t)

Needs a daemon with `analytics.site` set (docs/DAEMON.md). Subscribes to MVTRACK_ANALYTICS_EVENTS
(analytics_event_t: an entry or exit is published once it is certain, `hold_s` after the border
was crossed, with the crossing's time as utime) and, with --counts, MVTRACK_SITE_COUNTS
(site_counts_t: occupancy and totals since the daemon started). Messages that do not decode are
reported on stderr and skipped. Needs PyPI's `lcm` and the generated types (docs/PYTHON.md).
Exit status: 0 (Ctrl-C, --count reached, or the end of a file:// log), 1 when --timeout passes
without a message or LCM cannot start, 2 on usage errors.
"""
import argparse
import json
import sys

import lcm

from mvtrack_msgs import (COUNTS_CHANNEL, EVENTS_CHANNEL, counts_to_dict, decode, event_to_dict,
                          format_counts, format_event, listen)
import mvtrack


def main():
    ap = argparse.ArgumentParser(description="Print mvtrack site analytics live.")
    ap.add_argument("--url", default=None, help="LCM URL (default: LCM's default)")
    ap.add_argument("--events-channel", default=EVENTS_CHANNEL, help="events channel")
    ap.add_argument("--counts-channel", default=COUNTS_CHANNEL, help="counts channel")
    ap.add_argument("--counts", action="store_true", help="also print the counts messages")
    ap.add_argument("--json", action="store_true", help="one JSON line per message")
    ap.add_argument("--count", type=int, default=0, help="exit after N events (0: never)")
    ap.add_argument("--timeout", type=float, default=0.0,
                    help="exit with status 1 after this many seconds without a message (0: never)")
    a = ap.parse_args()
    if a.count < 0 or a.timeout < 0:
        ap.error("--count and --timeout must be >= 0")

    try:
        lc = lcm.LCM(a.url) if a.url else lcm.LCM()
    except (RuntimeError, OSError) as e:
        print(f"print_site.py: cannot start LCM ({a.url or 'default URL'}): {e}", file=sys.stderr)
        return 1
    received = [0]

    def decoded(channel, data, cls):
        try:
            msg = decode(data)
        except ValueError as e:
            print(f"print_site.py: {channel}: {e}", file=sys.stderr)
            return None
        if not isinstance(msg, cls):
            print(f"print_site.py: {channel}: not a {cls.__name__} message", file=sys.stderr)
            return None
        return msg

    def on_event(channel, data):
        e = decoded(channel, data, mvtrack.analytics_event_t)
        if e is None:
            return
        received[0] += 1
        print(json.dumps({"event": event_to_dict(e)}) if a.json else format_event(e), flush=True)

    def on_counts(channel, data):
        c = decoded(channel, data, mvtrack.site_counts_t)
        if c is not None:
            print(json.dumps({"counts": counts_to_dict(c)}) if a.json
                  else "\n".join(format_counts(c)), flush=True)

    lc.subscribe(a.events_channel, on_event)
    if a.counts:
        lc.subscribe(a.counts_channel, on_counts)
    return listen(lc, "print_site.py", a.events_channel, received, a.count, a.timeout, "events")


if __name__ == "__main__":
    sys.exit(main())
