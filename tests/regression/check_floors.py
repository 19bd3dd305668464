#!/usr/bin/env python3
"""Checks the metrics of one `mvtrack eval --json` report against the bounds of a floors file.

Usage: check_floors.py KEY FLOORS_FILE EVAL_JSON
Floors file lines: `KEY METRIC >=|<= BOUND` ('#' starts a comment); only KEY's lines are
checked and there must be at least one. Metrics: mota, idf1, hota, mpjpe_m, false_positives,
misses, id_switches, id_transfers, id_fragmentations, predicted_ids (tracking); pcp_average,
pcp_actorN (PCP); bone_cv_mean, bone_cv_worst_track (bone-length stability, `--pcp`);
median_distance_m, p90_distance_m,
precision, recall, mean_abs_count_difference, moda, modp_m, false_positives, misses
(--points). Exit 0 when every bound holds.
Shared by replay_regression_test.sh (datasets) and sim_regression_test.sh (simulated scenes).
"""
import json
import sys

key, floors_path, eval_path = sys.argv[1:]
report = json.load(open(eval_path, encoding="utf-8"))
metrics = {}
if "tracking" in report:
    clear = report["tracking"]["clear_mot"]
    metrics.update({
        "mota": clear["mota"],
        "idf1": report["tracking"]["identity"]["idf1"],
        "mpjpe_m": (report["tracking"].get("pose") or {}).get("mpjpe_m"),
        "false_positives": clear["num_false_positives"],
        "misses": clear["num_misses"],
        "id_switches": clear["num_switches"],
        "hota": report["tracking"]["hota"]["hota"],
        "id_transfers": report["tracking"]["coverage"]["num_id_transfers"],
        "id_fragmentations": report["tracking"]["coverage"]["num_id_fragmentations"],
        "predicted_ids": clear["num_unique_predictions"],
    })
if "pcp" in report:
    metrics["pcp_average"] = report["pcp"]["average_pcp"]
    for actor in report["pcp"]["actors"]:
        metrics[f"pcp_actor{actor['actor_id']}"] = actor["pcp"]
if report.get("bones", {}).get("num_tracks", 0) > 0:
    metrics["bone_cv_mean"] = report["bones"]["cv_mean"]
    metrics["bone_cv_worst_track"] = report["bones"]["cv_worst_track"]
if "points" in report:
    for name in ("median_distance_m", "p90_distance_m", "precision", "recall",
                 "mean_abs_count_difference", "moda", "modp_m", "false_positives", "misses"):
        metrics[name] = report["points"][name]

checked, failures = 0, []
for number, raw in enumerate(open(floors_path, encoding="utf-8"), 1):
    line = raw.split("#", 1)[0].split()
    if not line:
        continue
    where = f"{floors_path}:{number}"
    if len(line) != 4 or line[2] not in (">=", "<="):
        sys.exit(f"{where}: expected 'KEY METRIC >=|<= BOUND', got {raw.strip()!r}")
    name, op, bound = line[1], line[2], float(line[3])
    if line[0] != key:
        continue
    if name not in metrics:
        sys.exit(f"{where}: unknown metric {name!r} (known: {', '.join(sorted(metrics))})")
    value = metrics[name]
    ok = value is not None and (value >= bound if op == ">=" else value <= bound)
    print(f"{key} {name} = {value} (bound {op} {bound}): {'ok' if ok else 'REGRESSION'}")
    checked += 1
    if not ok:
        failures.append(f"{name} = {value}, bound {op} {bound} ({where})")
if checked == 0:
    sys.exit(f"{floors_path}: no bound for {key}")
if failures:
    sys.exit("FAIL: " + key + " regressed: " + "; ".join(failures))
print(f"PASS: {key}: {checked} bounds hold, replays byte-identical")
