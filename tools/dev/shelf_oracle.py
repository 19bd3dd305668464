#!/usr/bin/env python3
"""Upper bound of Shelf PCP reachable from the 2D detections (docs/ACCURACY.md).

An oracle that knows the 3D ground truth builds every joint of every actor-frame as the best
(closest to the ground truth) of all two-view triangulations (linear, normalised DLT rows) of
2D points of that joint, over every pair of the five views. Two variants:

  grouped: the points of the per-person OpenPose skeletons (shelf/derived, what
           `mvtrack convert shelf` feeds the tracker);
  raw:     every raw OpenPose candidate of the joint (4d_association/detection/*.txt: also the
           candidates the greedy PAF grouping attached to nobody), within --radius px of the
           ground truth's projection (what any regrouping of the candidates could use).

The eight limb parts (upper/lower arms and legs) are scored with the PCP rule of `mvtrack eval`
(mean endpoint error <= 0.5 x GT part length). Head and torso depend on derived joints (ears,
neck, mid hip) that the ground truth does not contain, so the oracle cannot pick them: they are
counted correct, which makes the printed averages optimistic bounds.

Python 3 standard library only. Usage:
  python3 tools/dev/shelf_oracle.py --gt build/results-run/shelf/ground_truth.jsonl
          [--data ../shared/data] [--radius 200]
"""

import argparse
import itertools
import json
import math
import os
import sys

LIMB_JOINTS = ["r_ankle", "r_knee", "r_hip", "l_hip", "l_knee", "l_ankle", "r_wrist",
               "r_elbow", "r_shoulder", "l_shoulder", "l_elbow", "l_wrist"]  # shelf14 0-11
LIMB_PARTS = [(0, 1), (1, 2), (3, 4), (4, 5), (6, 7), (7, 8), (9, 10), (10, 11)]
BODY25 = {"r_shoulder": 2, "r_elbow": 3, "r_wrist": 4, "l_shoulder": 5, "l_elbow": 6,
          "l_wrist": 7, "r_hip": 9, "r_knee": 10, "r_ankle": 11, "l_hip": 12, "l_knee": 13,
          "l_ankle": 14}
# BODY25 limbs in the order of 4D Association's detection files (PAF blocks follow the joints).
BODY25_PAF_LIMBS = [(1, 8), (9, 10), (10, 11), (8, 9), (8, 12), (12, 13), (13, 14), (1, 2),
                    (2, 3), (3, 4), (2, 17), (1, 5), (5, 6), (6, 7), (5, 18), (1, 0), (0, 15),
                    (0, 16), (15, 17), (16, 18), (14, 19), (19, 20), (14, 21), (11, 22),
                    (22, 23), (11, 24)]


def fail(msg):
    sys.exit(f"shelf_oracle: {msg}")


def load_calibration(path):
    cal = json.load(open(path, encoding="utf-8"))
    cams = {}
    for c in range(5):
        e = cal[str(c)]
        k, rt = e["K"], e["RT"]
        p = [[sum(k[r * 3 + i] * rt[i * 4 + col] for i in range(3)) for col in range(4)]
             for r in range(3)]
        w, h = e["imgSize"]
        cams[c] = (p, w, h)
    return cams


def project(p, x):
    u = [sum(p[r][i] * x[i] for i in range(3)) + p[r][3] for r in range(3)]
    return u[0] / u[2], u[1] / u[2]


def det3(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def triangulate(pa, xa, pb, xb):
    rows = []
    for p, x in ((pa, xa), (pb, xb)):
        for u, r in ((x[0], 0), (x[1], 1)):
            row = [u * p[2][k] - p[r][k] for k in range(4)]
            n = math.sqrt(sum(v * v for v in row[:3]))
            rows.append([v / n for v in row])
    m = [[sum(a[i] * a[j] for a in rows) for j in range(3)] for i in range(3)]
    b = [-sum(a[i] * a[3] for a in rows) for i in range(3)]
    d = det3(m)
    if abs(d) < 1e-12:
        return None
    out = []
    for k in range(3):
        mk = [[b[i] if j == k else m[i][j] for j in range(3)] for i in range(3)]
        out.append(det3(mk) / d)
    return out


def parse_raw(path, w, h):
    """Per frame, per BODY25 joint: the raw candidates (x px, y px)."""
    tok = open(path, encoding="utf-8").read().split()
    i = 2
    num_frames = int(tok[1])
    frames = []
    for _ in range(num_frames):
        joints = []
        for _ in range(25):
            n = int(tok[i]); i += 1
            xs = [float(v) for v in tok[i:i + n]]; i += n
            ys = [float(v) for v in tok[i:i + n]]; i += n
            i += n  # scores
            joints.append([(x * (w - 1), y * (h - 1)) for x, y in zip(xs, ys)])
        for a, b in BODY25_PAF_LIMBS:
            i += len(joints[a]) * len(joints[b])
        frames.append(joints)
    return frames


def load_grouped(path):
    doc = json.load(open(path, encoding="utf-8"))
    return {f["frame_index"]: f["persons"] for f in doc["frames"]}


def grouped_candidates(persons, cam_p, gt_joints, joint):
    """The joint's point in the skeleton of this view that belongs to the actor (nearest
    shoulders/hips to the GT projection, within 40 px on average)."""
    best = None
    for person in persons:
        ds = []
        for name in ("r_shoulder", "l_shoulder", "r_hip", "l_hip"):
            kp = person["keypoints"][BODY25[name]]
            if kp[2] > 0:
                u = project(cam_p, gt_joints[LIMB_JOINTS.index(name)])
                ds.append(math.hypot(kp[0] - u[0], kp[1] - u[1]))
        if ds and (best is None or sum(ds) / len(ds) < best[0]):
            best = (sum(ds) / len(ds), person)
    if best is None or best[0] > 40:
        return []
    kp = best[1]["keypoints"][BODY25[joint]]
    return [(kp[0], kp[1])] if kp[2] > 0 else []


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--gt", required=True, help="ground_truth.jsonl of `mvtrack convert shelf`")
    ap.add_argument("--data", default=os.environ.get("MVTRACK_DATA", os.path.join(
        os.path.dirname(__file__), "..", "..", "..", "shared", "data")))
    ap.add_argument("--radius", type=float, default=200.0,
                    help="raw candidates farther than this from the GT projection are ignored")
    ap.add_argument("--actors", default="0,1,2")
    args = ap.parse_args()
    shelf = os.path.join(args.data, "shelf")
    if not os.path.isdir(shelf):
        fail(f"no Shelf data at {shelf} (--data or $MVTRACK_DATA)")
    cams = load_calibration(os.path.join(shelf, "4d_association", "calibration.json"))
    raw = {c: parse_raw(os.path.join(shelf, "4d_association", "detection", f"{c}.txt"),
                        cams[c][1], cams[c][2]) for c in range(5)}
    grouped = {c: load_grouped(os.path.join(shelf, "derived", f"persons2d_body25_cam{c}.json"))
               for c in range(5)}
    gt = {}
    for line in open(args.gt, encoding="utf-8"):
        o = json.loads(line)
        gt[o["frame"]] = {t["id"]: t["joints"] for t in o["tracks"]}
    first = min(gt)
    actors = [int(a) for a in args.actors.split(",")]
    print(f"Shelf PCP oracle: best two-view triangulation per joint (GT-selected); limb parts "
          f"scored, head and torso counted correct; frames {first}-{max(gt)}")
    for variant in ("grouped", "raw"):
        averages = []
        for a in actors:
            ok = total = 0
            for f in sorted(gt):
                if a not in gt[f]:
                    continue
                g = gt[f][a]
                est = []
                for si, name in enumerate(LIMB_JOINTS):
                    target = g[si]
                    cand = {}
                    for c in range(5):
                        if variant == "raw":
                            u = project(cams[c][0], target)
                            cand[c] = [x for x in raw[c][f - first][BODY25[name]]
                                       if math.hypot(x[0] - u[0], x[1] - u[1]) <= args.radius]
                        else:
                            cand[c] = grouped_candidates(grouped[c].get(f - first, []),
                                                         cams[c][0], g, name)
                    best = None
                    for ca, cb in itertools.combinations(range(5), 2):
                        for xa in cand[ca]:
                            for xb in cand[cb]:
                                x = triangulate(cams[ca][0], xa, cams[cb][0], xb)
                                if x is None:
                                    continue
                                e = math.dist(x, target)
                                if best is None or e < best[0]:
                                    best = (e, x)
                    est.append(best[1] if best else None)
                for s, e in LIMB_PARTS:
                    total += 1
                    if est[s] is None or est[e] is None:
                        continue
                    length = math.dist(g[s], g[e])
                    if (math.dist(est[s], g[s]) + math.dist(est[e], g[e])) / 2 <= 0.5 * length:
                        ok += 1
                frames_parts = 2  # head and torso, counted correct
                ok += frames_parts
                total += frames_parts
            pcp = 100.0 * ok / total if total else float("nan")
            averages.append(pcp)
            print(f"  {variant:8s} actor {a}: PCP {pcp:6.2f}  ({total - ok} failed limb parts "
                  f"of {total})")
        print(f"  {variant:8s} average: {sum(averages) / len(averages):6.2f}")


if __name__ == "__main__":
    main()
