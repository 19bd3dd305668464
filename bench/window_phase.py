#!/usr/bin/env python3
"""How much of a result is the window phase (docs/ACCURACY.md "Window phase").

The tracker's window grid starts at the multiple of the window step delta at or before the
stream's first frame (docs/DECISIONS.md "Frames and windows"), so where the window boundaries
fall in a recording is fixed by its frame numbers. Shifting every frame number by k (and the
ground truth with it) moves the boundaries by k frames and changes nothing else. This replays
a converted dataset at shifts 0..SHIFTS-1 (the output shifted back before `mvtrack eval`, so its
frame ranges stay those of the ground truth) and prints each shift's scores and their spread.

Usage: window_phase.py DATA_DIR OUT_DIR [--shifts N] [--mvtrack PATH] [REPLAY ARGS...]
       [-- EVAL ARGS...]

DATA_DIR is a `mvtrack convert` output (calibration.yaml, detections.lcmlog,
ground_truth.jsonl). Example (EPFL Terrace through the default detector model):

    mvtrack convert epfl --corruption default --data ../shared/data --out /tmp/epfl
    bench/window_phase.py /tmp/epfl /tmp/epfl_phase --mvtrack build/ci/tools/mvtrack \\
        --mode boxes --layout none

Standard library only: the LCM log is rewritten with the documented event format and the
camera_detections_t field layout (fingerprint, utime, frame: the int64 at bytes 16-24).
"""
import json
import os
import statistics
import struct
import subprocess
import sys

SYNC = 0xEDA1DA01
HEADER = struct.Struct(">IqqII")  # sync, event number, timestamp, channel length, data length


def shift_log(src, dst, shift):
    """Copies LCM log `src` to `dst` with every camera_detections_t frame number + shift."""
    with open(src, "rb") as f, open(dst, "wb") as out:
        while True:
            head = f.read(HEADER.size)
            if len(head) < HEADER.size:
                break
            sync, number, stamp, clen, dlen = HEADER.unpack(head)
            if sync != SYNC:
                raise SystemExit(f"{src}: not an LCM log (sync word {sync:#x})")
            channel = f.read(clen)
            data = bytearray(f.read(dlen))
            if channel.startswith(b"MVTRACK_DETECTIONS") and len(data) >= 24:
                frame = struct.unpack_from(">q", data, 16)[0]
                struct.pack_into(">q", data, 16, frame + shift)
            out.write(HEADER.pack(sync, number, stamp, clen, len(data)) + channel + bytes(data))


def shift_jsonl(src, dst, shift):
    with open(src) as f, open(dst, "w") as out:
        for line in f:
            d = json.loads(line)
            d["frame"] += shift
            out.write(json.dumps(d) + "\n")


def scores(path):
    d = json.load(open(path))
    t = d["tracking"]
    out = {"MOTA": 100 * t["clear_mot"]["mota"], "IDF1": 100 * t["identity"]["idf1"],
           "HOTA": 100 * t["hota"]["hota"]}
    if "pcp" in d:
        out["PCP"] = 100 * d["pcp"]["average_pcp"]
    return out


def main(argv):
    if len(argv) < 3 or argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(argv) > 1 else 2
    data, work = argv[1], argv[2]
    rest = argv[3:]
    shifts, mvtrack = 20, "mvtrack"
    replay, evaluate = [], []
    target = replay
    i = 0
    while i < len(rest):
        if rest[i] == "--shifts":
            shifts = int(rest[i + 1])
            i += 2
        elif rest[i] == "--mvtrack":
            mvtrack = rest[i + 1]
            i += 2
        elif rest[i] == "--":
            target = evaluate
            i += 1
        else:
            target.append(rest[i])
            i += 1
    os.makedirs(work, exist_ok=True)
    rows = []
    for k in range(shifts):
        log, shifted = f"{work}/detections_{k}.lcmlog", f"{work}/shifted_{k}.jsonl"
        tracks, report = f"{work}/tracks_{k}.jsonl", f"{work}/eval_{k}.json"
        shift_log(f"{data}/detections.lcmlog", log, k)
        subprocess.run([mvtrack, "replay", "--quiet", "--calibration", f"{data}/calibration.yaml",
                        *replay, "--jsonl", shifted, log], check=True, stdout=subprocess.DEVNULL)
        shift_jsonl(shifted, tracks, -k)
        subprocess.run([mvtrack, "eval", "--gt", f"{data}/ground_truth.jsonl", tracks, *evaluate,
                        "--json", report], check=True, stdout=subprocess.DEVNULL)
        rows.append(scores(report))
        print(f"shift {k:2d}: " + "  ".join(f"{m} {v:6.2f}" for m, v in rows[-1].items()),
              flush=True)
        for p in (log, shifted):
            os.remove(p)
    for m in rows[0]:
        v = [r[m] for r in rows]
        print(f"{m}: mean {statistics.mean(v):.2f}, sd {statistics.pstdev(v):.2f}, "
              f"min {min(v):.2f}, max {max(v):.2f} over {len(v)} shifts")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
