#!/usr/bin/env python3
"""A zone that dies and comes back (issue 43): what happens to everyone else, and how soon
its own people are tracked again.

Usage: zone_outage.py CALIBRATION.yaml ZONES.yaml GT.jsonl BASELINE.jsonl OUTAGE.jsonl ZONE FROM TO

BASELINE is `mvtrack replay --zones` of the log, OUTAGE the same with `--zone-outage
ZONE:FROM:TO` (seconds from the first capture time). Ground-truth people belong to the zone
whose own cameras' mean position is nearest (as in zone_crossings.py). Prints, for the people
of the other zones during the outage, their track-frames (a track within 0.5 m) and id changes
(the nearest track's id differs from their previous tracked frame's) in both runs; and, for the
people
in ZONE when it returns, how long after TO each is tracked again (median, 90th percentile,
largest). Standard library only.
"""
import json
import math
import sys

from zone_crossings import camera_centres, load, zones_of


def nearest_id(tracks, pos):
    best = min(((math.dist(pos[:2], q[:2]), tid) for tid, q in tracks), default=(99.0, None))
    return best[1] if best[0] <= 0.5 else None


def main(argv):
    cal, zones_path, gt_path, base_path, out_path, dead = argv[1:7]
    t_from, t_to = float(argv[7]), float(argv[8])
    centres = camera_centres(cal)
    anchors = []
    for name, cams in zones_of(zones_path):
        xs = [centres[c] for c in cams if c in centres]
        anchors.append((name, sum(p[0] for p in xs) / len(xs), sum(p[1] for p in xs) / len(xs)))
    zone_at = lambda p: min(anchors, key=lambda a: (a[1] - p[0]) ** 2 + (a[2] - p[1]) ** 2)[0]
    gt, base, out = load(gt_path), load(base_path), load(out_path)
    utimes = {}
    for line in open(gt_path):
        d = json.loads(line)
        utimes[d["frame"]] = d["utime"]
    t0 = min(utimes.values())
    sec = lambda f: (utimes[f] - t0) / 1e6
    # Track-frames, and id changes (a person's nearest track id differs from the one of their
    # previous tracked frame), of the other zones' people during the outage, in each run.
    figures = []
    for run in (base, out):
        tracked = changes = 0
        last = {}
        for f in sorted(gt):
            if not (t_from <= sec(f) < t_to):
                continue
            for pid, p in gt[f]:
                if zone_at(p) == dead:
                    continue
                tid = nearest_id(run.get(f, []), p)
                if tid is None:
                    continue
                tracked += 1
                changes += pid in last and last[pid] != tid
                last[pid] = tid
        figures.append((tracked, changes))
    (tb, cb), (to, co) = figures
    print("other zones' people during the outage: %d track-frames (%.2f %% of the run without "
          "the outage), %d id changes (without the outage: %d)"
          % (to, 100.0 * to / max(1, tb), co, cb))
    first_frame_after = min(f for f in gt if sec(f) >= t_to)
    waits = []
    for pid, p in gt[first_frame_after]:
        if zone_at(p) != dead:
            continue
        for f in sorted(f for f in gt if sec(f) >= t_to):
            if sec(f) > t_to + 10:
                waits.append(float("inf"))
                break
            q = dict(gt[f]).get(pid)
            if q is not None and nearest_id(out.get(f, []), q) is not None:
                waits.append(sec(f) - t_to)
                break
    waits.sort()
    if waits:
        n = len(waits)
        print("its people when it returns: %d; tracked again after median %.2f s, 90th "
              "percentile %.2f s, at most %.2f s" % (n, waits[n // 2], waits[int(0.9 * (n - 1))],
                                                      waits[-1]))


if __name__ == "__main__":
    main(sys.argv)
