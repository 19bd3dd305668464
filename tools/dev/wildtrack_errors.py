#!/usr/bin/env python3
"""Classifies the false positives and misses of WILDTRACK footprints (docs/ACCURACY.md).

Usage: wildtrack_errors.py GROUND_TRUTH.jsonl TRACKS.jsonl INPUT_POINTS.jsonl
  GROUND_TRUTH: `mvtrack convert wildtrack`'s ground_truth.jsonl; TRACKS: our footprints;
  INPUT_POINTS: its ground_points.jsonl (MVDeTr's own ground points, the tracker's input).
Per frame, footprints inside the annotated area are matched one-to-one to the ground truth
within 0.5 m (as `mvtrack eval --points --area -3,9,-9,27`); the input points are matched the
same way. Each unmatched footprint is classified by the first rule that holds:
  inherited  within 0.5 m of an input point that is itself unmatched (MVDeTr's false point);
  duplicate  within 1 m of a ground-truth person matched to another footprint;
  displaced  within 1.5 m of a ground-truth person;
  ghost      farther from every ground-truth person.
Each miss: whether the input had a point for that person. Needs python3-numpy, python3-scipy.
"""
import json
import sys

import numpy as np
from scipy.optimize import linear_sum_assignment

AREA = (-3.0, 9.0, -9.0, 27.0)
GATE = 0.5


def load(path):
    frames = {}
    for line in open(path, encoding="utf-8"):
        o = json.loads(line)
        frames[o["frame"]] = [np.array(t["position"][:2]) for t in o["tracks"]]
    return frames


def inside(p):
    return AREA[0] <= p[0] <= AREA[1] and AREA[2] <= p[1] <= AREA[3]


def match(a, b):
    """Indices i -> j of a one-to-one assignment within GATE, the most pairs first."""
    if not a or not b:
        return {}
    d = np.array([[np.linalg.norm(x - y) for y in b] for x in a])
    rows, cols = linear_sum_assignment(np.where(d <= GATE, d, 1e6))
    return {i: j for i, j in zip(rows, cols) if d[i, j] <= GATE}


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    gt, tracks, points = (load(p) for p in sys.argv[1:])
    fp, fn = {}, {}
    for f in sorted(gt):
        g = gt[f]
        pred = [p for p in tracks.get(f, []) if inside(p)]
        inp = points.get(f, [])
        m, mi = match(g, pred), match(g, inp)
        matched = set(m.values())
        inp_false = [inp[j] for j in range(len(inp)) if j not in set(mi.values())]
        for j, p in enumerate(pred):
            if j in matched:
                continue
            near = min([np.linalg.norm(p - q) for q in g] + [np.inf])
            if any(np.linalg.norm(p - q) <= GATE for q in inp_false):
                kind = "inherited (an unmatched input point within 0.5 m)"
            elif any(np.linalg.norm(p - g[i]) <= 1.0 for i in m):
                kind = "duplicate (within 1 m of a person matched to another footprint)"
            elif near <= 1.5:
                kind = "displaced (within 1.5 m of a person)"
            else:
                kind = "ghost (farther than 1.5 m from everybody)"
            fp[kind] = fp.get(kind, 0) + 1
        for i in range(len(g)):
            if i not in m:
                kind = "the input had it" if i in mi else "the input missed it too"
                fn[kind] = fn.get(kind, 0) + 1
    print(f"false positives: {sum(fp.values())}")
    for k, v in sorted(fp.items(), key=lambda x: -x[1]):
        print(f"  {v:4d}  {k}")
    print(f"misses: {sum(fn.values())}")
    for k, v in sorted(fn.items(), key=lambda x: -x[1]):
        print(f"  {v:4d}  {k}")


if __name__ == "__main__":
    main()
