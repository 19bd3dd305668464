#!/usr/bin/env python3
"""Border crossings of a site split into zones (issue 43): does a person keep their id?

Usage: zone_crossings.py CALIBRATION.yaml ZONES.yaml GT.jsonl TRACKS.jsonl [--fps 30]

Each ground-truth footprint belongs to the zone whose own cameras' mean position (x, y of the
camera centres) is nearest. A crossing is a person's change of zone that holds for at least 1 s
on both sides. The id before is the track within 0.5 m of the person 1 s before the crossing
(the nearest), the id after likewise 1 s after; the crossing keeps its id when both exist and are
equal. Prints the crossings, those that kept their id, those without a track on one side, and the
ids that changed; of those, the id transfers (the id after had been another person's: the
nearest track within 0.5 m of another ground-truth person before the crossing), also as a share
of all predicted ids (the issue's "id transfers at borders"). Standard library only.
"""
import json
import math
import re
import sys


def camera_centres(path):
    """Camera id -> (x, y) of its centre, -R^T t, from a canonical calibration file (what
    `mvtrack calib import` and `mvtrack sim` write: `R: [[...], [...], [...]]`, `t: [...]`)."""
    centres = {}
    for block in re.split(r"\n\s*-\s+id:\s*", open(path).read())[1:]:
        cid = int(re.match(r"(\d+)", block).group(1))
        r = [float(v) for v in re.findall(r"-?[\d.]+(?:e-?\d+)?",
                                          re.search(r"\bR:\s*(\[\[.*?\]\])", block).group(1))]
        t = [float(v) for v in re.search(r"\bt:\s*\[([^\]]*)\]", block).group(1).split(",")]
        rot = [r[0:3], r[3:6], r[6:9]]
        centres[cid] = tuple(-sum(rot[k][i] * t[k] for k in range(3)) for i in range(2))
    return centres


def zones_of(path):
    zones, name = [], None
    for line in open(path):
        m = re.match(r"\s*-\s*name:\s*(\S+)", line)
        if m:
            name = m.group(1)
        m = re.match(r"\s*cameras:\s*\[([^\]]*)\]", line)
        if m and name:
            zones.append((name, [int(v) for v in m.group(1).split(",") if v.strip()]))
            name = None
    return zones


def load(path):
    frames = {}
    for line in open(path):
        d = json.loads(line)
        frames[d["frame"]] = [(t["id"], t["position"]) for t in d["tracks"] if t["position"]]
    return frames


def main(argv):
    fps = 30.0
    if "--fps" in argv:
        i = argv.index("--fps")
        fps = float(argv[i + 1])
        del argv[i:i + 2]
    cal, zones_path, gt_path, pred_path = argv[1:5]
    centres = camera_centres(cal)
    zones = zones_of(zones_path)
    anchors = []
    for name, cams in zones:
        xs = [centres[c] for c in cams if c in centres]
        anchors.append((name, sum(p[0] for p in xs) / len(xs), sum(p[1] for p in xs) / len(xs)))
    zone_at = lambda p: min(anchors, key=lambda a: (a[1] - p[0]) ** 2 + (a[2] - p[1]) ** 2)[0]
    gt, pred = load(gt_path), load(pred_path)
    hold = int(round(fps))
    paths = {}
    for f in sorted(gt):
        for pid, p in gt[f]:
            paths.setdefault(pid, []).append((f, p, zone_at(p)))
    # Which ground-truth people each predicted id was the nearest track (within 0.5 m) of, and
    # from which frame on.
    first_of = {}  # (id, person) -> first frame
    for f, people in gt.items():
        for tid, q in pred.get(f, []):
            best = min(((math.dist(p[:2], q[:2]), pid) for pid, p in people), default=(99.0, None))
            if best[0] <= 0.5:
                key = (tid, best[1])
                first_of[key] = min(first_of.get(key, f), f)
    persons_of = {}
    for (tid, pid), f in first_of.items():
        persons_of.setdefault(tid, []).append((f, pid))
    crossings = kept = missing = changed = transfers = 0
    for pid, path in paths.items():
        i = 0
        while i < len(path):
            j = i
            while j < len(path) and path[j][2] == path[i][2]:
                j += 1
            k = j
            while k < len(path) and path[k][2] == (path[j][2] if j < len(path) else None):
                k += 1
            # path[i:j] one zone, path[j:k] the next: a crossing at j if both last >= 1 s.
            if j < len(path) and j - i >= hold and k - j >= hold:
                crossings += 1
                def nearest(frame, pos):
                    best = min(((math.dist(pos[:2], q[:2]), tid) for tid, q in pred.get(frame, [])),
                               default=(99.0, None))
                    return best[1] if best[0] <= 0.5 else None
                before = nearest(path[j - hold][0], path[j - hold][1])
                after = nearest(path[j + hold - 1][0], path[j + hold - 1][1])
                if before is None or after is None:
                    missing += 1
                elif before == after:
                    kept += 1
                else:
                    changed += 1
                    if any(q != pid and f < path[j][0] for f, q in persons_of.get(after, [])):
                        transfers += 1
            i = j
    share = 100.0 * kept / max(1, kept + changed)
    ids = {tid for tracks in pred.values() for tid, _ in tracks}
    print("border crossings: %d; id kept %d, changed %d (%.2f %% kept of those tracked on both "
          "sides), not tracked on one side %d; id transfers %d (%.2f %% of %d ids)"
          % (crossings, kept, changed, share, missing, transfers,
             100.0 * transfers / max(1, len(ids)), len(ids)))


if __name__ == "__main__":
    main(sys.argv)
