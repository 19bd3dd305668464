#!/usr/bin/env python3
"""compare_tracks.py GOT.jsonl WANT.jsonl [--frames-only]

GOT: the JSON lines printed by examples/python (read_log.py --json, print_tracks.py --json), one
per tracks3d_t. WANT: `mvtrack replay --jsonl` output for the same run (canonical tracks JSONL,
read here with the standard library, independently of the examples). Every frame must match:
frame, utime, the set of track ids, each track's position (metres) and its joints (valid
joints' positions; invalid ones None), within the JSONL's 4 decimals. Exit status 1 with the first differences.
"""
import json
import sys


def close(a, b):
    # The JSONL has 4 decimals (round to nearest): 0.5e-4 plus float slack.
    return abs(a - b) <= 0.6e-4


def same_point(a, b):
    if a is None or b is None:
        return a is None and b is None
    return len(a) == len(b) and all(close(x, y) for x, y in zip(a, b))


def main():
    got = [json.loads(l) for l in open(sys.argv[1], encoding="utf-8") if l.strip()]
    want = [json.loads(l) for l in open(sys.argv[2], encoding="utf-8") if l.strip()]
    errors = []
    if len(got) != len(want):
        errors.append(f"{len(got)} messages, the replay JSONL has {len(want)} frames")
    for g, w in zip(got, want):
        where = f"frame {w['frame']}"
        if (g["frame"], g["utime"]) != (w["frame"], w["utime"]):
            errors.append(f"{where}: frame/utime {g['frame']}/{g['utime']} != {w['frame']}/{w['utime']}")
            continue
        g["tracks"].sort(key=lambda t: t["id"])
        gids = [t["id"] for t in g["tracks"]]
        wids = [t["id"] for t in w["tracks"]]
        if gids != wids:
            errors.append(f"{where}: track ids {gids} != {wids}")
            continue
        for gt, wt in zip(g["tracks"], w["tracks"]):
            if not same_point(gt["position"], wt["position"]):
                errors.append(f"{where} id {gt['id']}: position {gt['position']} != {wt['position']}")
            wj = wt.get("joints") or []
            if len(gt["joints"]) != len(wj):
                errors.append(f"{where} id {gt['id']}: {len(gt['joints'])} joints != {len(wj)}")
                continue
            for k, (a, b) in enumerate(zip(gt["joints"], wj)):
                if not same_point(a, b):
                    errors.append(f"{where} id {gt['id']} joint {k}: {a} != {b}")
    if errors:
        for e in errors[:10]:
            print("FAIL:", e, file=sys.stderr)
        return 1
    tracks = sum(len(w["tracks"]) for w in want)
    print(f"compare_tracks: {len(got)} frames, {tracks} track states match")
    return 0


if __name__ == "__main__":
    sys.exit(main())
