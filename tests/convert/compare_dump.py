#!/usr/bin/env python3
"""Compares a decoded detections log (mvtrack_convert_check --dump) with the converter's source,
read here independently of the C++ code:

  compare_dump.py jsonl INPUT.jsonl DUMP      every input line is one event, in (frame, camera)
                                             order, with the same values (float precision)
  compare_dump.py shelf DATA_ROOT DUMP        the persons of shelf/derived/persons2d_body25_cam*.json
  compare_dump.py campus-clean DATA_ROOT DUMP the poses of campus/.../annotation_2d.json
  compare_dump.py campus-zero-rates DATA_ROOT DUMP
                                             the same through the corruption model with every
                                             rate 0: keypoints outside the 360x288 image lose
                                             their confidence, people left with fewer than 2
                                             keypoints are dropped
  compare_dump.py wildtrack DATA_ROOT DUMP    the boxes of wildtrack/rest/MVDeTr_test.json

For the datasets the detections of each camera-frame are compared as multisets (the order of a
frame's detections carries no meaning), and boxes and scores are recomputed from the keypoints
with the documented rule (keypoint bounds grown by 10 % of their height on each side, at least
1 px; score = mean confidence of the detected keypoints). Exit status 1 with the first
differences on stderr.
"""
import json
import sys
from collections import defaultdict

errors = []


def fail(msg):
    errors.append(msg)


def close(a, b):
    return abs(a - b) <= 1e-6 * max(1.0, abs(a), abs(b))


def read_dump(path):
    events = [json.loads(line) for line in open(path, encoding="utf-8")]
    keys = [(e["frame"], e["camera"]) for e in events]
    if keys != sorted(keys) or len(set(keys)) != len(keys):
        fail("dump: events are not strictly ordered by (frame, camera)")
    return events, {(e["frame"], e["camera"]): e for e in events}


def box_from_keypoints(kps):
    pts = [(x, y) for x, y, c in kps if c > 0]
    xs = [p[0] for p in pts]
    ys = [p[1] for p in pts]
    pad = max(1.0, 0.1 * (max(ys) - min(ys)))
    return [min(xs) - pad, min(ys) - pad, max(xs) + pad, max(ys) + pad]


def pose_key(kps):
    # Detected keypoints only (the position of an undetected one carries no meaning).
    return tuple((round(x, 2), round(y, 2), round(c, 4)) if c > 0 else (0, 0, 0) for x, y, c in kps)


def compare_poses(where, got_dets, want_poses, layout):
    """want_poses: lists of [x, y, conf]."""
    if len(got_dets) != len(want_poses):
        fail(f"{where}: {len(got_dets)} detections, expected {len(want_poses)}")
        return
    got_sorted = sorted(got_dets, key=lambda d: pose_key(d["keypoints"]))
    want_sorted = sorted(want_poses, key=pose_key)
    for d, want in zip(got_sorted, want_sorted):
        if d.get("layout") != layout:
            fail(f"{where}: layout {d.get('layout')}, expected {layout}")
            return
        for (gx, gy, gc), (wx, wy, wc) in zip(d["keypoints"], want):
            if not close(gc, wc) or (wc > 0 and (not close(gx, wx) or not close(gy, wy))):
                fail(f"{where}: keypoint {[gx, gy, gc]} != {[wx, wy, wc]}")
                return
        want_box = box_from_keypoints(want)
        if not all(close(a, b) for a, b in zip(d["box"], want_box)):
            fail(f"{where}: box {d['box']} != {want_box}")
        confs = [c for _, _, c in want if c > 0]
        if not close(d["score"], sum(confs) / len(confs)):
            fail(f"{where}: score {d['score']} != mean confidence {sum(confs) / len(confs)}")


def compare_dataset(dump_path, expected, layout, compare):
    """expected: (frame, camera) -> list of source detections."""
    events, by_key = read_dump(dump_path)
    for key, e in by_key.items():
        compare(f"frame {key[0]} camera {key[1]}", e["detections"], expected.get(key, []), layout)
    missing = [k for k, v in expected.items() if v and k not in by_key]
    if missing:
        fail(f"{len(missing)} source camera-frames with detections have no event, e.g. {missing[0]}")
    return len(events)


def mode_jsonl(input_path, dump_path):
    lines = [json.loads(line) for line in open(input_path, encoding="utf-8")]
    events, by_key = read_dump(dump_path)
    want_keys = sorted((l["frame"], l["camera"]) for l in lines)
    if [(e["frame"], e["camera"]) for e in events] != want_keys:
        fail("the events are not the input lines in (frame, camera) order")
    for l in lines:
        key = (l["frame"], l["camera"])
        e = by_key.get(key)
        if e is None:
            continue
        where = f"frame {key[0]} camera {key[1]}"
        if e["utime"] != l["utime"]:
            fail(f"{where}: utime {e['utime']} != {l['utime']}")
        if len(e["detections"]) != len(l["detections"]):
            fail(f"{where}: {len(e['detections'])} detections != {len(l['detections'])}")
            continue
        for i, (g, w) in enumerate(zip(e["detections"], l["detections"])):
            w_emb = w.get("embedding", [])
            ok = (all(close(a, b) for a, b in zip(g["box"], w["box"])) and close(g["score"], w["score"])
                  and g.get("layout") == w.get("layout")
                  and len(g.get("keypoints", [])) == len(w.get("keypoints", []))
                  and all(close(a, b) for gk, wk in zip(g.get("keypoints", []), w.get("keypoints", []))
                          for a, b in zip(gk, wk))
                  and len(g.get("embedding", [])) == len(w_emb)
                  and all(close(a, b) for a, b in zip(g.get("embedding", []), w_emb)))
            if not ok:
                fail(f"{where}: detection {i} differs: {g} != {w}")
    return len(events)


def mode_shelf(root, dump_path):
    expected = defaultdict(list)
    for cam in range(5):
        doc = json.load(open(f"{root}/shelf/derived/persons2d_body25_cam{cam}.json", encoding="utf-8"))
        for f in doc["frames"]:
            for p in f["persons"]:
                kps = [[x, y, min(s, 1.0)] for x, y, s in p["keypoints"]]
                expected[(300 + f["frame_index"], cam)].append(kps)
    return compare_dataset(dump_path, expected, "body25", compare_poses)


def campus_poses(root, in_image_only):
    doc = json.load(open(f"{root}/campus/crossview_longcw/annotation_2d.json", encoding="utf-8"))
    width, height = doc["image_wh"]
    expected = defaultdict(list)
    for v in doc["frames"].values():
        cam = int(v["camera"].replace("Camera", ""))
        frame = round(v["timestamp"] / 0.04)
        for p in v["poses"]:
            kps = [[x, y, s] for (x, y), s in zip(p["points_2d"], p["scores"])]
            if in_image_only:
                kps = [[x, y, s if 0 <= x <= width and 0 <= y <= height else 0] for x, y, s in kps]
                if sum(1 for _, _, s in kps if s > 0) < 2:
                    continue
            expected[(frame, cam)].append(kps)
    return expected


def mode_campus_clean(root, dump_path):
    return compare_dataset(dump_path, campus_poses(root, False), "shelf14", compare_poses)


def mode_campus_zero_rates(root, dump_path):
    return compare_dataset(dump_path, campus_poses(root, True), "shelf14", compare_poses)


def compare_boxes(where, got_dets, want_boxes, layout):
    got = sorted(tuple(round(v, 3) for v in d["box"]) for d in got_dets)
    want = sorted(tuple(round(v, 3) for v in b) for b in want_boxes)
    if got != want:
        fail(f"{where}: boxes {got[:3]}... != {want[:3]}...")
    for d in got_dets:
        if "keypoints" in d or d["score"] != 1:
            fail(f"{where}: expected box-only detections with score 1")


def mode_wildtrack(root, dump_path):
    doc = json.load(open(f"{root}/wildtrack/rest/MVDeTr_test.json", encoding="utf-8"))
    expected = defaultdict(list)
    for frame, entries in doc.items():
        for left, top, w, h, _, cam in entries:
            expected[(int(frame), cam)].append([left, top, left + w, top + h])
    return compare_dataset(dump_path, expected, "none", compare_boxes)


def main():
    modes = {"jsonl": mode_jsonl, "shelf": mode_shelf, "campus-clean": mode_campus_clean,
             "campus-zero-rates": mode_campus_zero_rates,
             "wildtrack": mode_wildtrack}
    if len(sys.argv) != 4 or sys.argv[1] not in modes:
        print(__doc__, file=sys.stderr)
        return 2
    n = modes[sys.argv[1]](sys.argv[2], sys.argv[3])
    if errors:
        for e in errors[:10]:
            print("FAIL:", e, file=sys.stderr)
        print(f"{len(errors)} difference(s)", file=sys.stderr)
        return 1
    print(f"compare_dump {sys.argv[1]}: {n} events match the source")
    return 0


if __name__ == "__main__":
    sys.exit(main())
