#!/usr/bin/env python3
"""Publishes your detector's output to mvtrack over LCM: reads detections in mvtrack's
JSON-lines format (docs/FORMATS.md, "JSON-lines detections": one camera-frame per line, boxes,
optional keypoints and re-identification embeddings with their `embedding_model`) and sends
each line as one camera_detections_t on MVTRACK_DETECTIONS, where mvtrackd listens.

  publish_detections.py DETECTIONS.jsonl [--lcm-url URL] [--realtime]

  --lcm-url URL   LCM provider (default: LCM's default, udpm://239.255.76.67:7667?ttl=0);
                  file:///path/out.lcmlog?mode=w records a log for `mvtrack replay` instead
  --realtime      pace the messages by their utime (as a live detector would)

A detector of your own would build the same message per frame (see `to_message`): embeddings
of any length and scale (mvtrack normalises them), one model per camera. Needs PyPI's `lcm` and
the generated types (docs/PYTHON.md). Exit status: 0 published, 1 unreadable input (the line
is named), 2 usage.
"""
import argparse
import json
import sys
import time

import lcm

import mvtrack
from mvtrack_msgs import DETECTIONS_PREFIX


def to_message(line):
    """One JSON-lines camera-frame (a dict) as a camera_detections_t."""
    msg = mvtrack.camera_detections_t()
    msg.utime = int(line["utime"])
    msg.frame = int(line["frame"])
    msg.camera_id = int(line["camera"])
    width, height = line.get("image_size", [0, 0])
    msg.image_width, msg.image_height = int(width), int(height)
    for d in line["detections"]:
        det = mvtrack.detection_t()
        det.x_min, det.y_min, det.x_max, det.y_max = (float(v) for v in d["box"])
        det.score = float(d["score"])
        det.keypoint_layout = d.get("layout", "")
        for x, y, conf in d.get("keypoints", []):
            k = mvtrack.keypoint2d_t()
            k.x, k.y, k.confidence = float(x), float(y), float(conf)
            det.keypoints.append(k)
        det.num_keypoints = len(det.keypoints)
        det.embedding = [float(v) for v in d.get("embedding", [])]
        det.num_embedding = len(det.embedding)
        det.embedding_model = d.get("embedding_model", "") if det.embedding else ""
        msg.detections.append(det)
    msg.num_detections = len(msg.detections)
    return msg


def main():
    ap = argparse.ArgumentParser(description="Publish JSON-lines detections to mvtrack over LCM.")
    ap.add_argument("detections", help="JSON-lines detections (docs/FORMATS.md)")
    ap.add_argument("--lcm-url", default=None, help="LCM provider URL (default: LCM's default)")
    ap.add_argument("--realtime", action="store_true", help="pace messages by their utime")
    a = ap.parse_args()
    try:
        lines = open(a.detections, encoding="utf-8").read().splitlines()
    except OSError as e:
        print(f"publish_detections.py: cannot read {a.detections}: {e}", file=sys.stderr)
        return 1
    messages = []
    for number, text in enumerate(lines, 1):
        if not text.strip():
            continue
        try:
            messages.append(to_message(json.loads(text)))
        except (ValueError, KeyError, TypeError) as e:
            print(f"publish_detections.py: {a.detections}:{number}: {e}", file=sys.stderr)
            return 1
    lc = lcm.LCM(a.lcm_url) if a.lcm_url else lcm.LCM()
    start_wall, start_utime = time.monotonic(), messages[0].utime if messages else 0
    for msg in messages:
        if a.realtime:
            delay = (msg.utime - start_utime) / 1e6 - (time.monotonic() - start_wall)
            if delay > 0:
                time.sleep(delay)
        lc.publish(DETECTIONS_PREFIX, msg.encode())
    embeddings = sum(1 for m in messages for d in m.detections if d.num_embedding > 0)
    print(f"published {len(messages)} camera-frame(s), {embeddings} detection(s) with an "
          f"embedding", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
