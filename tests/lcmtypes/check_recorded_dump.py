#!/usr/bin/env python3
"""check_recorded_dump.py RECORDED_DUMP INPUT_DUMP TRACKS_JSONL VERSION

Checks the decoded values of a log recorded by `mvtrackd --record` (RECORDED_DUMP, the canonical
dump of tests/lcmtypes/sample_messages.h, which DecodeLog.java reproduced) against what was
written:
  - detections: the recorded camera_detections_t events are exactly the input log's events
    (INPUT_DUMP), as a multiset of (channel, every field);
  - tracks: the recorded final tracks3d_t events (layer 0) are, in order, the frames of the
    daemon's --tracks-jsonl (frame, utime, track ids, positions within the JSONL's 4 decimals),
    and as many provisional ones (layer 1) are on MVTRACK_TRACKS_NOW;
  - status: at least one tracker_status_t; version == VERSION; the cameras are the input's;
    per camera, received <= the input's events; last_frame within the input's frames.
Exit status 1 with the first differences.
"""
import json
import struct
import sys
from collections import Counter, defaultdict


def read_dump(path):
    """[(channel, type, {path: value})] in event order, and the raw lines per event."""
    events = []
    for line in open(path, encoding="utf-8"):
        line = line.rstrip("\n")
        if line.startswith("event "):
            parts = dict(p.split("=", 1) for p in line.split()[2:])
            events.append((parts["channel"], parts["type"], {}, []))
        else:
            key, value = line.split("=", 1)
            events[-1][2][key] = value
            events[-1][3].append(line)
    return events


def real(v):
    return struct.unpack(">d", bytes.fromhex(v[2:]))[0]


def main():
    recorded = read_dump(sys.argv[1])
    inputs = read_dump(sys.argv[2])
    frames = [json.loads(l) for l in open(sys.argv[3], encoding="utf-8")]
    version = sys.argv[4]
    errors = []

    # Detections.
    want = Counter((c, tuple(lines)) for c, t, f, lines in inputs if t == "camera_detections_t")
    got = Counter((c, tuple(lines)) for c, t, f, lines in recorded if t == "camera_detections_t")
    if not want:
        errors.append("the input log has no detections")
    if got != want:
        errors.append(f"recorded detections differ from the input: {sum((got - want).values())} "
                      f"extra, {sum((want - got).values())} missing")
    input_frames = [int(f["frame"]) for c, t, f, _ in inputs if t == "camera_detections_t"]
    per_camera = Counter(int(f["camera_id"]) for c, t, f, _ in inputs if t == "camera_detections_t")

    # Tracks.
    tracks = [f for c, t, f, _ in recorded if t == "tracks3d_t" and f["layer"] == "0"]
    provisional = [f for c, t, f, _ in recorded if t == "tracks3d_t" and f["layer"] == "1"]
    if len(provisional) != len(frames):
        errors.append(f"{len(provisional)} provisional tracks3d_t events (layer 1), the JSONL has "
                      f"{len(frames)} frames")
    if {c for c, t, f, _ in recorded if t == "tracks3d_t" and f["layer"] == "1"} != {
            "MVTRACK_TRACKS_NOW"}:
        errors.append("the provisional layer is not (only) on MVTRACK_TRACKS_NOW")
    if len(tracks) != len(frames) or not frames:
        errors.append(f"{len(tracks)} tracks3d_t events, the JSONL has {len(frames)} frames")
    for f, w in zip(tracks, frames):
        where = f"frame {w['frame']}"
        if (int(f["frame"]), int(f["utime"])) != (w["frame"], w["utime"]):
            errors.append(f"{where}: frame/utime {f['frame']}/{f['utime']} != {w['frame']}/{w['utime']}")
            continue
        n = int(f["num_tracks"])
        got_tracks = sorted((int(f[f"tracks[{i}].id"]),
                             [real(f[f"tracks[{i}].position[{k}]"]) for k in range(3)])
                            for i in range(n))
        want_tracks = [(t["id"], t["position"]) for t in w["tracks"]]
        if [i for i, _ in got_tracks] != [i for i, _ in want_tracks]:
            errors.append(f"{where}: ids {[i for i, _ in got_tracks]} != {[i for i, _ in want_tracks]}")
            continue
        for (i, p), (_, q) in zip(got_tracks, want_tracks):
            if q is None or any(abs(a - b) > 0.6e-4 for a, b in zip(p, q)):
                errors.append(f"{where} id {i}: position {p} != {q}")

    # Status.
    statuses = [f for c, t, f, _ in recorded if t == "tracker_status_t"]
    if not statuses:
        errors.append("no tracker_status_t event")
    for s in statuses:
        if s["version"] != json.dumps(version):
            errors.append(f"status version {s['version']} != \"{version}\"")
        cams = [int(s[f"cameras[{i}].camera_id"]) for i in range(int(s["num_cameras"]))]
        if sorted(cams) != sorted(per_camera):
            errors.append(f"status cameras {cams} != input cameras {sorted(per_camera)}")
        for i, cam in enumerate(cams):
            if int(s[f"cameras[{i}].received"]) > per_camera.get(cam, 0):
                errors.append(f"status: camera {cam} received {s[f'cameras[{i}].received']} > "
                              f"{per_camera.get(cam, 0)} sent")
        last = int(s["last_frame"])
        if last != -1 and not min(input_frames) <= last <= max(input_frames):
            errors.append(f"status last_frame {last} outside the input frames")

    if errors:
        for e in errors[:10]:
            print("FAIL:", e, file=sys.stderr)
        return 1
    channels = sorted({c for c, _, _, _ in recorded})
    print(f"check_recorded_dump: {sum(want.values())} detection events, {len(tracks)} track "
          f"frames, {len(statuses)} status messages match; channels {' '.join(channels)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
