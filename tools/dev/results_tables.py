#!/usr/bin/env python3
"""Tables of docs/RESULTS.md from the evaluations tools/dev/results.sh wrote.

  results_tables.py --out R --commit SHA --dirty N --version V --mvtrack P --data D
      reads R/manifest.tsv and R/runs/*.eval.json, writes R/results.md and R/results.json;
  results_tables.py --splice R/results.md docs/RESULTS.md
      replaces the text between the GENERATED markers of docs/RESULTS.md with R/results.md;
  results_tables.py --floors R
      prints the bound lines of tests/regression/floors.txt for the runs `shelf`, `campus` and
      `wildtrack` of R/results.json: the measured values with the margins stated
      in that file.

Standard library only. The paper's numbers below are copied from the LaTeX source in
../shared/paper (Yang et al., "A Unified Multi-view Multi-person Tracking Framework"), tables
"campus_shelf" (Table 6), "ablation_campus_shelf" (Table 7), "ablation_MMPTRACK" (Table 8) and
"multi-wildtrack_ablation" (Table 5).
"""

import argparse
import datetime
import json
import os
import re
import sys

BEGIN = "<!-- BEGIN GENERATED RESULTS: tools/dev/results.sh --update-docs rewrites this part -->"
END = "<!-- END GENERATED RESULTS -->"
# The README's results table: rendered into RESULTS.md's generated part between these markers,
# copied into README.md between the same markers by --readme (results.sh --update-docs), and
# compared by CTest docs/readme_results (tools/dev/check_readme_results.py).
README_BEGIN = "<!-- BEGIN README RESULTS TABLE: copied from docs/RESULTS.md by tools/dev/results.sh --update-docs -->"
README_END = "<!-- END README RESULTS TABLE -->"
# Published figures the README's table quotes (each peer's own paper, not re-run).
REST_WILDTRACK = (81.6, 85.7)       # ReST (ICCV 2023), MVDeTr's boxes: MOTA, IDF1
LMGP_WILDTRACK = (97.1, 98.2)       # LMGP (CVPR 2023), offline: MOTA, IDF1
PAPER_WILDTRACK = (94.0, 94.7, 11)  # Yang et al. Table 8 (LMGP's detections): MOTA, IDF1, IDSW

# Paper Table 6 (published numbers; each method with its own detector / input).
# (method, actor 1, actor 2, actor 3, average PCP, MOTA or None)
PAPER_T6_CAMPUS = [
    ("Belagiannis et al. (CVPR 14)", 82.0, 72.4, 73.7, 75.8, None),
    ("Belagiannis et al. (ECCVW 14)", 83.0, 73.0, 78.0, 78.0, None),
    ("Belagiannis et al. (TPAMI 16)", 93.5, 75.7, 84.4, 84.5, None),
    ("Ershadi-Nasab et al. (MTA 18)", 94.2, 92.9, 84.6, 90.6, None),
    ("Ye et al. (ECCV 22)", 96.5, 94.1, 97.9, 96.2, None),
    ("Dong et al. (CVPR 19)", 97.6, 93.3, 98.0, 96.3, None),
    ("VoxelPose (ECCV 20)", 97.6, 93.8, 98.8, 96.7, None),
    ("VoxelTrack (TPAMI 22)", 98.1, 93.7, 98.3, 96.7, 89.3),
    ("Yang et al. w/o appearance (the paper)", 98.2, 94.6, 98.2, 97.0, 89.4),
    ("Yang et al. w/ appearance (the paper)", 98.2, 94.6, 98.2, 97.0, 90.8),
]
PAPER_T6_SHELF = [
    ("Belagiannis et al. (CVPR 14)", 66.1, 65.0, 83.2, 71.4, None),
    ("Belagiannis et al. (ECCVW 14)", 75.0, 67.0, 86.0, 76.0, None),
    ("Belagiannis et al. (TPAMI 16)", 75.3, 69.7, 87.6, 77.5, None),
    ("Ershadi-Nasab et al. (MTA 18)", 93.3, 75.9, 94.8, 88.0, None),
    ("Dong et al. (CVPR 19)", 98.8, 94.1, 97.8, 96.9, None),
    ("VoxelPose (ECCV 20)", 99.3, 94.1, 97.6, 97.0, None),
    ("VoxelTrack (TPAMI 22)", 98.6, 94.9, 97.7, 97.1, 94.4),
    ("4D Association (CVPR 20)", 99.0, 96.2, 97.6, 97.6, None),
    ("Ye et al. (ECCV 22)", 99.4, 96.0, 97.5, 97.6, None),
    ("Yang et al. w/o appearance (the paper)", 99.5, 96.0, 97.7, 97.7, 94.6),
    ("Yang et al. w/ appearance (the paper)", 99.5, 96.0, 97.7, 97.7, 94.6),
]
# Paper Table 7: (variant, actor 1, actor 2, actor 3, average).
PAPER_T7 = {
    "campus": [("w/ Triangulation", 96.1, 93.0, 90.7, 93.3),
               ("w/ Triangulation+RANSAC", 97.6, 93.0, 95.6, 95.4),
               ("w/ CMMT", 98.2, 94.6, 98.2, 97.0)],
    "shelf": [("w/ Triangulation", 96.6, 92.0, 97.7, 95.4),
              ("w/ Triangulation+RANSAC", 98.5, 93.8, 97.7, 96.6),
              ("w/ CMMT", 99.5, 96.0, 97.7, 97.7)],
}
# Paper Table 8 (MMPTRACK, w/o appearance): (nu, delta, lambda, MOTA %, IDF1 %, FPS).
PAPER_T8 = [(50, 30, 0.3, 95, 84, 67), (30, 20, 0.3, 94, 83, 60), (70, 50, 0.3, 94, 84, 72),
            (50, 30, 0.1, 94, 81, 67), (50, 30, 0.6, 95, 83, 67)]
# Paper Table 5 (WILDTRACK, w/o appearance): (method, IDF1 %, MOTA %, IDs).
PAPER_T5 = [("complete-linkage clustering", 87.3, 73.6, 24), ("PDNC", 94.7, 94.0, 11)]

ASSOCIATION = [("pdnc", "PDNC (default)"),
               ("association_complete_linkage_empty_as_zero", "complete linkage, empty = 0 (c)"),
               ("association_complete_linkage_empty_as_upper",
                "complete linkage, empty = 1.0 (d)"),
               ("association_single_linkage_empty_as_upper", "single linkage, empty = 1.0 (e)")]
TRIANGULATION = [("triangulation_dlt", "DLT (\"w/ Triangulation\")"),
                 ("triangulation_ransac", "DLT + RANSAC"),
                 ("cmmt", "CMMT (default)")]
REFINEMENT = [("default", "**defaults**"),
              ("refinement_no_smoothing", "no temporal smoothing (`smooth_half_window: 0`)"),
              ("refinement_smooth_every_joint",
               "smoothing every joint, not only two-view ones (`smooth_max_views: 1000`)"),
              ("refinement_fit_skeleton",
               "skeleton fit with the track's bone lengths (`fit_skeleton: true`, issue 40)"),
              ("linking_no_gap_bridging", "no gap bridging (`bridge_max_gap_s: 0`)"),
              ("linking_no_duplicate_detection",
               "no duplicate detection (`linking.duplicate_distance_m: 0`)")]
WINDOWS = [(50, 30, 0.3), (30, 20, 0.3), (70, 50, 0.3), (50, 30, 0.1), (50, 30, 0.6)]


def pct(x, digits=1):
    return "n/a" if x is None else f"{100.0 * x:.{digits}f}"


def num(x, digits=1):
    return "n/a" if x is None else f"{x:.{digits}f}"


def mm(x):
    return "n/a" if x is None else f"{1000.0 * x:.1f}"


def table(header, rows):
    out = ["| " + " | ".join(header) + " |",
           "|" + "|".join("---" if i == 0 else "---:" for i in range(len(header))) + "|"]
    for r in rows:
        out.append("| " + " | ".join(str(c) for c in r) + " |")
    return "\n".join(out) + "\n"


def load(out_dir):
    runs = {}
    with open(os.path.join(out_dir, "manifest.tsv"), encoding="utf-8") as f:
        lines = f.read().splitlines()
    for line in lines[1:]:
        rid, ds, config, commands, eval_json, replay_log = line.split("\t")
        with open(os.path.join(out_dir, eval_json), encoding="utf-8") as f:
            report = json.load(f)
        replay = None
        if replay_log != "-":
            with open(os.path.join(out_dir, replay_log), encoding="utf-8") as f:
                replay = f.read()
        runs[rid] = {"dataset": ds, "config": config, "commands": commands.split(" && "),
                     "metrics": metrics(report), "replay_summary": replay_summary(replay)}
    return runs


def load_analytics(out_dir):
    """The analytics runs of R/analytics.tsv (absent in results directories before issue 41)."""
    path = os.path.join(out_dir, "analytics.tsv")
    if not os.path.exists(path):
        return {}
    out = {}
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    for line in lines[1:]:
        aid, tracks, site, command, json_path = line.split("\t")
        with open(os.path.join(out_dir, json_path), encoding="utf-8") as f:
            out[aid] = {"tracks_run": tracks, "site": site, "command": command,
                        "report": json.load(f)}
    return out


def analytics_tables(A):
    """RESULTS.md's analytics section: per run, its regions and lines against the ground truth."""
    md = ["\n### Analytics against ground truth (issue 41)\n\n"
          "`mvtrack analytics --gt`: the tracker's tracks and the ground truth's tracks through the "
          "same site file and rules (docs/DECISIONS.md \"Analytics\"); entries and crossings as "
          "counted, error = (counted - ground truth) / ground truth; occupancy compared in every "
          "ground-truth frame (exact: the same number of people; MAE: mean absolute difference); "
          "dwell error per visit matched by time overlap. Regions and lines: "
          "docs/examples/sites/.\n\n"]
    def err(n, gt):
        if gt == 0:
            return "0.0" if n == 0 else "n/a"
        return f"{100.0 * (n - gt) / gt:+.1f}"
    hdr = ["run", "region", "entries (gt)", "entry error %", "exits (gt)", "occupancy exact %",
           "occupancy MAE", "dwell error median / p95 s", "visits matched"]
    rows = []
    for aid, a in A.items():
        for r in a["report"]["regions"]:
            frames = r.get("occupancy_frames", 0)
            dm, dp = r.get("dwell_error_median_s"), r.get("dwell_error_p95_s")
            rows.append([f"`{aid}`", r["name"], f"{r['entries']} ({r['gt_entries']})",
                         err(r["entries"], r["gt_entries"]), f"{r['exits']} ({r['gt_exits']})",
                         pct(r["occupancy_frames_exact"] / frames if frames else None),
                         num(r["occupancy_abs_error_sum"] / frames if frames else None, 3),
                         (f"{dm:.2f} / {dp:.2f}" if dm is not None else "n/a"),
                         f"{r['visits_matched']} / {r['gt_visits']}"])
    md.append(table(hdr, rows))
    md.append("\n")
    hdr = ["run", "line", "left_to_right (gt)", "error %", "right_to_left (gt)", "error %"]
    rows = []
    for aid, a in A.items():
        for l in a["report"]["lines"]:
            rows.append([f"`{aid}`", l["name"], f"{l['left_to_right']} ({l['gt_left_to_right']})",
                         err(l["left_to_right"], l["gt_left_to_right"]),
                         f"{l['right_to_left']} ({l['gt_right_to_left']})",
                         err(l["right_to_left"], l["gt_right_to_left"])])
    md.append(table(hdr, rows))
    return "".join(md)


def replay_summary(text):
    if text is None:
        return None
    m = re.search(r"output: (\d+) frame\(s\), (\d+) track id\(s\), (\d+) track-frame\(s\)", text)
    if not m:
        return None
    return {"frames": int(m.group(1)), "track_ids": int(m.group(2)),
            "track_frames": int(m.group(3))}


def metrics(report):
    out = {}
    t = report.get("tracking")
    if t and t.get("valid"):
        c, i, p = t["clear_mot"], t["identity"], t["pose"]
        out.update({
            "mota": c["mota"], "motp_m": c["motp_m"], "idf1": i["idf1"], "idp": i["idp"],
            "idr": i["idr"], "mt": c["mostly_tracked"], "pt": c["partially_tracked"],
            "ml": c["mostly_lost"], "fp": c["num_false_positives"], "fn": c["num_misses"],
            "ids": c["num_switches"], "gt_objects": c["num_objects"],
            "gt_ids": c["num_unique_objects"], "pred_ids": c["num_unique_predictions"],
            "mpjpe_m": p["mpjpe_m"], "tracking_frames": t["frame_ranges"],
            "gate_m": t["threshold_m"], "distance": t["distance"],
            "hota": t["hota"]["hota"], "deta": t["hota"]["det_a"], "assa": t["hota"]["ass_a"],
            "id_transfers": t["coverage"]["num_id_transfers"],
            "id_fragmentations": t["coverage"]["num_id_fragmentations"]})
    pc = report.get("pcp")
    if pc and pc.get("valid"):
        out["pcp_average"] = pc["average_pcp"]
        out["pcp_actors"] = {str(a["actor_id"]): a["pcp"] for a in pc["actors"]}
        out["pcp_groups"] = dict(zip(pc["group_names"], pc["average_group_pcp"]))
        out["pcp_recall"] = pc["recall"]
    bones = report.get("bones")
    if bones and bones.get("num_tracks", 0) > 0:
        out["bone_cv_mean"] = bones["cv_mean"]
        out["bone_cv_worst_track"] = bones["cv_worst_track"]
    pt = report.get("points")
    if pt and pt.get("valid"):
        for k in ("num_frames", "num_reference", "num_predicted", "num_matched",
                  "frames_with_equal_count", "mean_abs_count_difference",
                  "mean_count_difference", "max_abs_count_difference", "precision", "recall",
                  "median_distance_m", "mean_distance_m", "p90_distance_m", "max_distance_m",
                  "gate_m", "false_positives", "misses", "moda", "modp", "modp_m",
                  "num_predicted_outside", "num_reference_outside"):
            out[k] = pt[k]
    return out


POINTS_HEADER = ["predicted", "GT", "TP", "FP", "FN", "MODA", "MODP %", "MODP m",
                 "precision", "recall", "run"]


def points_row(first, second, rid, m):
    """A row of POINTS_HEADER (after one or two label cells) for a --points run."""
    cells = [first] + ([second] if second is not None else [])
    return cells + [m.get("num_predicted"), m.get("num_reference"), m.get("num_matched"),
                    m.get("false_positives"), m.get("misses"), pct(m.get("moda")),
                    pct(m.get("modp")), num(m.get("modp_m"), 3), pct(m.get("precision")),
                    pct(m.get("recall")), f"`{rid}`"]


def actor_pcp(m, actor):
    return m.get("pcp_actors", {}).get(str(actor))


def bone_cv(m):
    if m.get("bone_cv_mean") is None:
        return ""
    return pct(m.get("bone_cv_mean"), 2) + " / " + pct(m.get("bone_cv_worst_track"), 2)


def pose_row(label, rid, m):
    return [label, pct(actor_pcp(m, 0)), pct(actor_pcp(m, 1)), pct(actor_pcp(m, 2)),
            pct(m.get("pcp_average")), mm(m.get("mpjpe_m")), bone_cv(m), pct(m.get("mota")),
            pct(m.get("idf1")), pct(m.get("hota")), m.get("id_transfers", "n/a"),
            m.get("id_fragmentations", "n/a"), m.get("mt", "n/a"), m.get("ml", "n/a"), m.get("fp", "n/a"),
            m.get("fn", "n/a"), m.get("ids", "n/a"), f"`{rid}`"]


POSE_HEADER = ["", "Actor 1", "Actor 2", "Actor 3", "Avg PCP", "MPJPE mm",
               "Bone CV % (mean / worst track)", "MOTA", "IDF1",
               "HOTA", "IDTR", "IDFRAG",
               "MT", "ML", "FP", "FN", "IDs", "run"]


def paper_rows(rows):
    return [[name + " †", num(a1), num(a2), num(a3), num(avg), "", "", num(mota) if mota else "",
             "", "", "", "", "", "", "", "", "", "Table 6"] for name, a1, a2, a3, avg, mota in rows]


def panoptic_cameras(out_dir, rid):
    path = os.path.join(out_dir, rid, "README.txt")
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError:
        return "?"
    m = re.search(r"into HD cameras (.*?)\s*\(camera id", text, re.S)
    return " ".join(m.group(1).split()).rstrip(",") if m else "?"


def readme_table(R):
    """The README's results table (markdown), every mvtrack and peer figure from the runs."""
    def paper(rows, col):
        return next(r[col] for r in rows if r[0] == "Yang et al. w/o appearance (the paper)")
    m = lambda rid: R[rid]["metrics"]
    hard = [m("campus_hard" if s == 1 else f"campus_hard_s{s}").get("pcp_average", 0.0)
            for s in range(1, 11)]
    w, wi = m("wildtrack"), m("wildtrack_input_mvdetr")
    wm, wa = m("wildtrack_tracking_1m"), m("wildtrack_annotated_tracking_1m")
    wd, e = m("wildtrack_annotated_all_default_tracking_1m"), m("epfl_05m")
    rows = [
        ["Shelf average PCP, actors 1-3 (standard protocol, 4D Association's head rule)",
         pct(m("shelf")["pcp_average"]), "4D Association " + pct(m("shelf_peer_4da")["pcp_average"]),
         f"{paper(PAPER_T6_SHELF, 4):.1f}"],
        ["Campus average PCP, actors 1-3", pct(m("campus")["pcp_average"]),
         "Cross-View Tracking " + pct(m("campus_peer_crossview")["pcp_average"]),
         f"{paper(PAPER_T6_CAMPUS, 4):.1f}"],
        ["Campus average PCP, the hard corruption level (`convert campus --corruption hard`; "
         f"seeds 1-10: mean {pct(sum(hard) / 10)})", pct(hard[0]), "–", "–"],
        ["WILDTRACK footprints, MODA (precision / recall), boxes, defaults",
         f"{pct(w['moda'])} ({pct(w['precision'])} / {pct(w['recall'])})",
         f"its input, MVDeTr's ground points: {pct(wi['moda'])} ({pct(wi['precision'])} / "
         f"{pct(wi['recall'])})", "– (tracking only, other detections)"],
        ["WILDTRACK tracking, test frames 360-399, 1 m: MOTA / IDF1, MVDeTr's boxes",
         f"{pct(wm['mota'])} / {pct(wm['idf1'])}",
         f"ReST (same input, its paper): {REST_WILDTRACK[0]} / {REST_WILDTRACK[1]}", "–"],
        ["WILDTRACK tracking, test frames, 1 m: MOTA / IDF1 / ID switches, annotated boxes",
         f"{pct(wa['mota'])} / {pct(wa['idf1'])} / {wa['ids']}",
         f"LMGP (offline, its paper): {LMGP_WILDTRACK[0]} / {LMGP_WILDTRACK[1]}",
         f"{PAPER_WILDTRACK[0]} / {PAPER_WILDTRACK[1]} / {PAPER_WILDTRACK[2]} (LMGP's detections)"],
        ["WILDTRACK tracking, all 400 frames, annotated boxes with the default detector model, "
         "1 m: IDF1", pct(wd["idf1"]), "–", "–"],
        [f"EPFL Terrace ({e['gt_ids']} people, {R['epfl_05m']['replay_summary']['frames']:,} frames), annotated boxes, "
         "0.5 m: MOTA / IDF1 / ids", f"{pct(e['mota'])} / {pct(e['idf1'])} / {e['pred_ids']}",
         "–", "–"],
    ]
    return table(["", "mvtrack", "peer (its own output, our evaluator)", "paper (Table 6)"], rows)


def render(out_dir, runs, info):
    R = runs
    md = []
    md.append(f"Generated {info['date']} by `tools/dev/results.sh` from commit `{info['commit']}`"
              f" ({info['dirty']} uncommitted paths in the tree at the time), mvtrack "
              f"`{info['version']}`. † = published number copied from the paper (each method "
              f"with its own detector), not re-run. Every other number is produced by the "
              f"command listed under its run id in [Commands](#commands). PCP and MOTA in %, "
              f"MPJPE in mm. MT/ML count ground-truth actors. HOTA (Luiten et al. 2021) in %; IDTR = "
              f"predicted ids covering two or more actors (id transfers), IDFRAG = actors "
              f"covered by two or more predicted ids (`mvtrack eval`, docs/FORMATS.md).\n")
    md.append("\n### The README's table\n\nREADME.md's \"Results on public data\" table, copied "
              "there by `tools/dev/results.sh --update-docs` (CTest `docs/readme_results` fails "
              "when the two differ):\n\n" + README_BEGIN + "\n" + readme_table(R) + README_END +
              "\n")

    # Targets.
    s, c = R["shelf"]["metrics"], R["campus"]["metrics"]
    w = R["wildtrack"]["metrics"]
    hard_mean = sum(R["campus_hard" if seed == 1 else f"campus_hard_s{seed}"]["metrics"]
                    .get("pcp_average", 0.0) for seed in range(1, 11)) / 10.0
    targets = [
        ("Shelf average PCP (actors 0, 1, 2)", ">= 98.0", pct(s.get("pcp_average")),
         s.get("pcp_average", 0) >= 0.98, "shelf"),
        ("Shelf lowest actor PCP (issue 17)", ">= 96.5",
         pct(min(actor_pcp(s, a) or 0.0 for a in range(3))),
         min(actor_pcp(s, a) or 0.0 for a in range(3)) >= 0.965, "shelf"),
        ("Shelf MOTA (4 actors)", ">= 94.6", pct(s.get("mota")), s.get("mota", -9) >= 0.946,
         "shelf"),
        ("Shelf IDF1 (4 actors)", ">= 90", pct(s.get("idf1")), s.get("idf1", 0) >= 0.90,
         "shelf"),
        ("Campus average PCP, default corruption", ">= 97.0", pct(c.get("pcp_average")),
         c.get("pcp_average", 0) >= 0.97, "campus"),
        ("Campus average PCP, hard corruption, mean of seeds 1-10 (issue 17)", ">= 97.5",
         pct(hard_mean, 2), hard_mean >= 0.975, "campus_hard, campus_hard_s2 … s10"),
        ("WILDTRACK MODA, defaults (issue 13)", ">= 88", pct(w.get("moda")),
         w.get("moda", -9) >= 0.88, "wildtrack"),
        ("WILDTRACK precision, defaults", ">= 92", pct(w.get("precision")),
         w.get("precision", 0) >= 0.92, "wildtrack"),
        ("WILDTRACK recall, defaults", ">= 90", pct(w.get("recall")),
         w.get("recall", 0) >= 0.90, "wildtrack"),
        ("WILDTRACK MODP (mean matched distance), defaults", "<= 0.12 m",
         num(w.get("modp_m"), 3) + " m",
         w.get("modp_m") is not None and w["modp_m"] <= 0.12, "wildtrack"),
    ]
    wt = R["wildtrack_annotated_tracking_1m"]["metrics"]
    wm = R["wildtrack_tracking_1m"]["metrics"]
    wm05 = R["wildtrack"]["metrics"]
    wa = R["wildtrack_annotated_all_default_tracking_1m"]["metrics"]
    miss, miss_in = (R["wildtrack_mvdetr_miss20"]["metrics"],
                     R["wildtrack_mvdetr_miss20_input"]["metrics"])
    ec, ed = R["epfl_05m"]["metrics"], R["epfl_default_05m"]["metrics"]
    targets += [
        ("WILDTRACK test frames, annotated boxes, 1 m: MOTA (issue 38)", ">= 95",
         pct(wt.get("mota")), wt.get("mota", -9) >= 0.95, "wildtrack_annotated_tracking_1m"),
        ("… IDF1", ">= 95", pct(wt.get("idf1")), wt.get("idf1", 0) >= 0.95,
         "wildtrack_annotated_tracking_1m"),
        ("… ID switches", "<= 10", str(wt.get("ids")), wt.get("ids", 99) <= 10,
         "wildtrack_annotated_tracking_1m"),
        ("WILDTRACK test frames, MVDeTr's boxes, 1 m: MOTA", ">= 88", pct(wm.get("mota")),
         wm.get("mota", -9) >= 0.88, "wildtrack_tracking_1m"),
        ("… IDF1", ">= 90", pct(wm.get("idf1")), wm.get("idf1", 0) >= 0.90,
         "wildtrack_tracking_1m"),
        ("… MODA at 0.5 m", ">= 88", pct(wm05.get("moda")), wm05.get("moda", -9) >= 0.88,
         "wildtrack"),
        ("… 20 % of the boxes removed: MODA not below its input points'",
         ">= " + pct(miss_in.get("moda")), pct(miss.get("moda")),
         miss.get("moda", -9) >= miss_in.get("moda", 9), "wildtrack_mvdetr_miss20"),
        ("WILDTRACK all 400 frames, annotated boxes, default detector model, 1 m: IDF1",
         ">= 85", pct(wa.get("idf1")), wa.get("idf1", 0) >= 0.85,
         "wildtrack_annotated_all_default_tracking_1m"),
        ("Terrace, annotated boxes as they are: IDF1 (0.5 m)", ">= 95", pct(ec.get("idf1")),
         ec.get("idf1", 0) >= 0.95, "epfl_05m"),
        ("Terrace, default detector model: IDF1 (0.5 m)", ">= 90", pct(ed.get("idf1")),
         ed.get("idf1", 0) >= 0.90, "epfl_default_05m"),
        ("… predicted ids", "<= 18", str(ed.get("pred_ids")), ed.get("pred_ids", 99) <= 18,
         "epfl_default_05m"),
    ]
    # Issue 41: the analytics of the simulator's 4 x 12 enter/leave room (9000 frames), boxes
    # and poses: the worst region or line of both runs.
    A = load_analytics(out_dir)
    sim = [A[k]["report"] for k in ("analytics_sim_enter_leave_boxes",
                                    "analytics_sim_enter_leave_poses") if k in A]
    if sim:
        regions = [r for rep in sim for r in rep["regions"]]
        lines = [l for rep in sim for l in rep["lines"]]
        occ = min(r["occupancy_frames_exact"] / r["occupancy_frames"] for r in regions)
        def rel(n, gt):
            return abs(n - gt) / gt if gt else (0.0 if n == 0 else float("inf"))
        entry = max(max(rel(r["entries"], r["gt_entries"]), rel(r["exits"], r["gt_exits"]))
                    for r in regions)
        cross = max(max(rel(l["left_to_right"], l["gt_left_to_right"]),
                        rel(l["right_to_left"], l["gt_right_to_left"])) for l in lines)
        dmed = max(r["dwell_error_median_s"] or 0.0 for r in regions)
        dp95 = max(r["dwell_error_p95_s"] or 0.0 for r in regions)
        rid = "analytics_sim_enter_leave_boxes, _poses"
        targets += [
            ("Simulated 4 x 12 enter/leave room, boxes and poses: occupancy exact, worst region "
             "(issue 41)", ">= 98 %", pct(occ), occ >= 0.98, rid),
            ("… entries and exits, worst region", "within 2 %", f"{100 * entry:.1f} %",
             entry <= 0.02, rid),
            ("… line crossings, worst line and direction", "within 2 %", f"{100 * cross:.1f} %",
             cross <= 0.02, rid),
            ("… dwell error per visit, median (worst region)", "<= 0.5 s", f"{dmed:.2f} s",
             dmed <= 0.5, rid),
            ("… dwell error per visit, 95th percentile (worst region)", "<= 2 s", f"{dp95:.2f} s",
             dp95 <= 2.0, rid),
        ]
    # Issue 41: the same room with people standing on region borders and lines for minutes:
    # entries (and crossings) counted per real one, worst region or line of both runs.
    linger = [A[k]["report"] for k in ("analytics_sim_linger_boxes", "analytics_sim_linger_poses")
              if k in A]
    if linger:
        def ratio(n, gt):
            return n / gt if gt else (1.0 if n == 0 else float("inf"))
        worst_entry = max(ratio(r["entries"], r["gt_entries"]) for rep in linger
                          for r in rep["regions"])
        worst_cross = max(max(ratio(l["left_to_right"], l["gt_left_to_right"]),
                              ratio(l["right_to_left"], l["gt_right_to_left"]))
                          for rep in linger for l in rep["lines"])
        rid = "analytics_sim_linger_boxes, _poses"
        targets += [
            ("Simulated room with people standing on region borders for minutes, boxes and "
             "poses: entries per real entry, worst region (issue 41)", "<= 1", f"{worst_entry:.3f}",
             worst_entry <= 1.0, rid),
            ("… crossings per real crossing, worst line and direction", "<= 1",
             f"{worst_cross:.3f}", worst_cross <= 1.0, rid),
        ]
    md.append("\n### Targets (issues 3, 13, 17, 38 and 41)\n\n")
    md.append(table(["target", "required", "measured", "met", "run"],
                    [[a, b, m_, "yes" if ok else "**no**", f"`{rid}`"]
                     for a, b, m_, ok, rid in targets]))

    md.append("\n### Shelf (real OpenPose detections), next to the paper's Table 6\n\n")
    rows = paper_rows(PAPER_T6_SHELF)
    rows.append(pose_row("**mvtrack** (these detections)", "shelf", R["shelf"]["metrics"]))
    rows.append(pose_row("mvtrack with the skeleton fit (`refinement.fit_skeleton: true`, issue "
                         "40)", "shelf_refinement_fit_skeleton",
                         R["shelf_refinement_fit_skeleton"]["metrics"]))
    rows.append(pose_row("mvtrack, head top by VoxelPose's `coco2campus3D` instead "
                         "(`--head-rule campus`)", "shelf_head_campus",
                         R["shelf_head_campus"]["metrics"]))
    rows.append(pose_row("4D Association (`windows` branch), its committed `skel.txt`, scored by "
                         "our evaluator", "shelf_peer_4da", R["shelf_peer_4da"]["metrics"]))
    rows.append(pose_row("4D Association (older `linux` branch, run here on these detections: "
                         "`4d_association_linux/skel.txt`), scored by our evaluator",
                         "shelf_peer_4da_linux", R["shelf_peer_4da_linux"]["metrics"]))
    md.append(table(POSE_HEADER, rows))

    md.append("\n### Campus (2D ground truth through the corruption model), next to the paper's "
              "Table 6\n\n")
    rows = paper_rows(PAPER_T6_CAMPUS)
    rows.append(pose_row("**mvtrack**, default corruption", "campus", R["campus"]["metrics"]))
    rows.append(pose_row("mvtrack with the skeleton fit (`refinement.fit_skeleton: true`)",
                         "campus_refinement_fit_skeleton",
                         R["campus_refinement_fit_skeleton"]["metrics"]))
    rows.append(pose_row("mvtrack, clean 2D ground truth (`--clean`)", "campus_clean",
                         R["campus_clean"]["metrics"]))
    rows.append(pose_row("mvtrack, hard corruption (`--corruption hard`, docs/ACCURACY.md)",
                         "campus_hard", R["campus_hard"]["metrics"]))
    rows.append(pose_row("Cross-View Tracking, its `result_3d.json`, scored by our evaluator",
                         "campus_peer_crossview", R["campus_peer_crossview"]["metrics"]))
    md.append(table(POSE_HEADER, rows))

    A = load_analytics(out_dir)
    if A:
        md.append(analytics_tables(A))

    md.append("\n### Ablation: cross-view association (PDNC vs hierarchical clustering)\n\n")
    md.append("Paper Table 5 (WILDTRACK, w/o appearance) †: " + "; ".join(
        f"{n}: IDF1 {a} %, MOTA {b} %, IDs {c_}" for n, a, b, c_ in PAPER_T5) + ".\n\n")
    hdr = ["dataset", "association", "Avg PCP", "MPJPE mm", "MOTA", "IDF1", "HOTA", "IDTR",
           "FP", "FN", "IDs", "run"]
    rows = []
    for ds in ("shelf", "campus"):
        for key, label in ASSOCIATION:
            rid = ds if key == "pdnc" else f"{ds}_{key}"
            m = R[rid]["metrics"]
            rows.append([ds.capitalize(), label, pct(m.get("pcp_average")), mm(m.get("mpjpe_m")),
                         pct(m.get("mota")), pct(m.get("idf1")), pct(m.get("hota")),
                         m.get("id_transfers"), m.get("fp"), m.get("fn"),
                         m.get("ids"), f"`{rid}`"])
    md.append(table(hdr, rows))
    rows = []
    for key, label in ASSOCIATION[:3]:
        rid = "wildtrack" if key == "pdnc" else f"wildtrack_{key}"
        rows.append(points_row("WILDTRACK", label, rid, R[rid]["metrics"]))
    md.append("\nWILDTRACK (footprints against its ground-truth positions, no ids: detection "
              "metrics only; section \"WILDTRACK\" below):\n\n")
    md.append(table(["dataset", "association"] + POINTS_HEADER, rows))

    md.append("\n### Ablation: triangulation (paper Table 7)\n\n")
    hdr = ["dataset", "triangulation", "Actor 1", "Actor 2", "Actor 3", "Avg PCP", "MPJPE mm",
           "MOTA", "run"]
    rows = []
    for ds in ("shelf", "campus"):
        for name, a1, a2, a3, avg in PAPER_T7[ds]:
            rows.append([ds.capitalize(), name + " †", num(a1), num(a2), num(a3), num(avg), "",
                         "", "Table 7"])
        for key, label in TRIANGULATION:
            rid = ds if key == "cmmt" else f"{ds}_{key}"
            m = R[rid]["metrics"]
            rows.append([ds.capitalize(), "mvtrack, " + label, pct(actor_pcp(m, 0)),
                         pct(actor_pcp(m, 1)), pct(actor_pcp(m, 2)), pct(m.get("pcp_average")),
                         mm(m.get("mpjpe_m")), pct(m.get("mota")), f"`{rid}`"])
    md.append(table(hdr, rows))

    md.append("\n### Ablation: window size ν, step δ and association cut λ (paper Table 8 "
              "grid)\n\n")
    md.append("The paper's Table 8 is measured on MMPTRACK (not available here) †; the same grid "
              "on Shelf and Campus:\n\n")
    hdr = ["ν", "δ", "λ", "paper MOTA †", "paper IDF1 †", "Shelf Avg PCP", "Shelf MOTA",
           "Shelf IDF1", "Shelf HOTA", "Shelf IDs", "Campus Avg PCP", "Campus MOTA",
           "Campus IDF1", "Campus HOTA", "Campus IDTR", "Campus IDs", "runs"]
    rows = []
    for (nu, delta, lam), (_, _, _, pm, pi, _) in zip(WINDOWS, PAPER_T8):
        v = f"window_nu{nu}_delta{delta}_lambda{lam}"
        sm, cm = R[f"shelf_{v}"]["metrics"], R[f"campus_{v}"]["metrics"]
        rows.append([nu, delta, lam, pm, pi, pct(sm.get("pcp_average")), pct(sm.get("mota")),
                     pct(sm.get("idf1")), pct(sm.get("hota")), sm.get("ids"),
                     pct(cm.get("pcp_average")), pct(cm.get("mota")), pct(cm.get("idf1")),
                     pct(cm.get("hota")), cm.get("id_transfers"), cm.get("ids"),
                     f"`shelf_{v}`, `campus_{v}`"])
    md.append(table(hdr, rows))

    md.append("\n### Ablation: the multi-frame stages (issue 17)\n\n")
    md.append("Each stage switched off (or widened) alone, the rest at the defaults. Bone CV: "
              "per predicted track of at least 50 frames in the evaluated frames, the "
              "coefficient of variation of each limb's length, mean over the 8 limbs (`mvtrack "
              "eval --pcp`, \"Bone lengths\"); the mean over tracks / the worst track. Campus hard: "
              "the `hard` corruption level (docs/DECISIONS.md) at seeds 1-10 (`campus_hard` is "
              "seed 1, `campus_hard_sN` seed N), the mean of the ten average PCPs; Panoptic: "
              "average PCP over all bones, 160906_band1 / 160906_band2.\n\n")
    hdr = ["variant", "Shelf Avg PCP", "Shelf Actor 2 (id 1)", "Shelf MPJPE mm",
           "Shelf bone CV % (mean / worst track)", "Campus Avg PCP",
           "Campus bone CV % (mean / worst track)",
           "Campus hard mean PCP (seeds 1-10)", "Campus hard worst seed",
           "Campus hard mean MOTA", "Panoptic 5 cams",
           "Panoptic 10 cams", "runs"]
    rows = []
    for key, label in REFINEMENT:
        suffix = "" if key == "default" else f"_{key}"
        hard_runs = [R[("campus_hard" if seed == 1 else f"campus_hard_s{seed}") + suffix]["metrics"]
                     for seed in range(1, 11)]
        hard = [m.get("pcp_average", 0.0) for m in hard_runs]
        hard_mota = sum(m.get("mota", 0.0) for m in hard_runs) / len(hard_runs)
        sm = R["shelf" + suffix]["metrics"]
        pan = {n: " / ".join(pct(R[f"panoptic_{seq}_c{n}{suffix}"]["metrics"].get("pcp_average"))
                             for seq in ("band1", "band2")) for n in (5, 10)}
        cm = R["campus" + suffix]["metrics"]
        cv = lambda m: (pct(m.get("bone_cv_mean"), 2) + " / " +
                        pct(m.get("bone_cv_worst_track"), 2))
        rows.append([label, pct(sm.get("pcp_average")), pct(actor_pcp(sm, 1)),
                     mm(sm.get("mpjpe_m")), cv(sm), pct(cm.get("pcp_average")), cv(cm),
                     pct(sum(hard) / len(hard), 2), pct(min(hard)), pct(hard_mota, 2), pan[5],
                     pan[10],
                     f"`shelf{suffix}`, `campus{suffix}`, `campus_hard{suffix}`, "
                     f"`campus_hard_sN{suffix}`, `panoptic_*{suffix}`"])
    md.append(table(hdr, rows))

    md.append("\n### CMU Panoptic with 5, 10 and 31 cameras\n\n")
    hdr = ["sequence", "cameras", "HD cameras used", "MPJPE mm", "PCP (all bones)",
           "PCP recall", "run"]
    rows = []
    for seq in ("band1", "band2"):
        for n in (5, 10, 31):
            rid = f"panoptic_{seq}_c{n}"
            m = R[rid]["metrics"]
            cams = panoptic_cameras(out_dir, rid) if n < 31 else "all 31 (00_00 … 00_30)"
            rows.append([f"160906_{seq}", n, cams, mm(m.get("mpjpe_m")), pct(m.get("pcp_average")),
                         pct(m.get("pcp_recall")), f"`{rid}`"])
    md.append(table(hdr, rows))

    md.append("\n### WILDTRACK: footprints against the ground-truth positions\n\n")
    md.append("The 40 test frames 360-399 (2 fps), MVDeTr's boxes in the 7 views as input, the "
              "ground-truth floor positions of MVDet's `gt.txt` (no person ids, so detection "
              "metrics only): per frame a one-to-one assignment within 0.5 m, points outside "
              "the annotated area (x in [-3, 9] m, y in [-9, 27] m) dropped on both sides; "
              "MODA = 1 - (FP + FN) / GT, MODP m = mean matched distance (MODP % = MVDet's "
              "mean of 1 - d / 0.5 m). Tracking metrics with person ids are in the next table.\n\n")
    rows = [points_row("MVDeTr's ground points (the tracker's input, box bottoms merged "
                       "across views)", None, "wildtrack_input_mvdetr",
                       R["wildtrack_input_mvdetr"]["metrics"])]
    for rid, label in (("wildtrack", "**mvtrack**, defaults (centre + ends, frame counts "
                                      "scaled to 2 fps)"),
                       ("wildtrack_box_point_center", "mvtrack, box centre only"),
                       ("wildtrack_box_point_bottom_center", "mvtrack, box bottom centre"),
                       ("wildtrack_frame_counts_at_any_rate",
                        "mvtrack, frame counts not scaled (`reference_fps: 0`: ν = 30 frames = "
                        "15 s)")):
        rows.append(points_row(label, None, rid, R[rid]["metrics"]))
    rows.append(points_row("MVDeTr's ground points of the boxes left after removing 20 % "
                           "(`--miss-rate 0.2`, seed 1)", None, "wildtrack_mvdetr_miss20_input",
                           R["wildtrack_mvdetr_miss20_input"]["metrics"]))
    rows.append(points_row("**mvtrack**, defaults, on the same boxes (20 % removed)", None,
                           "wildtrack_mvdetr_miss20", R["wildtrack_mvdetr_miss20"]["metrics"]))
    md.append(table(["footprints"] + POINTS_HEADER, rows))

    md.append("\n### WILDTRACK: tracking with person ids (issue 38)\n\n")
    md.append("Ground truth: the annotated floor positions with WILDTRACK's person ids "
              "(`opentraj/annotations_positions`, the original annotations; 2 fps). Scored by "
              "`mvtrack eval` (CLEAR MOT with py-motmetrics semantics, IDF1, HOTA) on the floor "
              "positions with a 1 m radius (the radius the WILDTRACK tracking literature uses, "
              "TrackTacular's `mot_bev.py`) and 0.5 m. Inputs: MVDeTr's boxes (test frames "
              "360-399, a detector's output; ReST tracks the same input); the annotated per-view "
              "boxes as they are (the \"ground-truth detections\" protocol of LMGP and of the "
              "paper's LMGP-based input); the same boxes through the seeded detector model "
              "(`--corruption default`: box edges moved by 2.1 % of the box height, 5 % misses, "
              "0.1 false boxes per view and frame). Defaults, no tuned file. † = published "
              "figures, each with its own input and protocol, not re-run.\n\n")
    hdr = ["input", "frames", "radius", "MOTA", "IDF1", "HOTA", "ID switches",
           "predicted / GT ids", "IDTR", "run"]
    rows = [["ReST † (online; MVDeTr's detections)", "360-399", "1 m", "81.6", "85.7", "–",
             "–", "–", "–", "–"],
            ["the paper, w/o appearance † (LMGP's detections, ground-truth based)", "360-399",
             "1 m", "94.0", "94.7", "–", "11", "–", "–", "–"],
            ["LMGP † (offline; ground-truth based detections)", "360-399", "1 m", "97.1",
             "98.2", "–", "–", "–", "–", "–"]]
    for ds, label, frames in (
            ("wildtrack", "**mvtrack**, MVDeTr's boxes", "360-399"),
            ("wildtrack_annotated", "**mvtrack**, annotated boxes as they are", "360-399"),
            ("wildtrack_annotated_all", "mvtrack, annotated boxes as they are", "0-399"),
            ("wildtrack_annotated_all_default", "mvtrack, annotated boxes, default detector "
             "model", "0-399")):
        for gate, suffix in (("1 m", "1m"), ("0.5 m", "05m")):
            rid = f"{ds}_tracking_{suffix}"
            m = R[rid]["metrics"]
            rows.append([label, frames, gate, pct(m.get("mota")), pct(m.get("idf1")),
                         pct(m.get("hota")), m.get("ids"),
                         f"{m.get('pred_ids')} / {m.get('gt_ids')}", m.get("id_transfers"),
                         f"`{rid}`"])
    md.append(table(hdr, rows))

    md.append("\n### EPFL Terrace: tracking with person ids (issue 38)\n\n")
    md.append("EPFL Terrace sequence 1: 4 cameras, 360 x 288, 25 fps, 9 people, frames "
              "59-4887. The cameras are recovered from the floor homographies (`mvtrack calib "
              "import homography`: square pixels, principal point at the image centre, focal "
              "length from the homography, floor unit from a 1.7 m person-height prior; "
              "docs/FORMATS.md). Detections: the annotated per-view boxes, as they are or "
              "through the default detector model; ground truth: the mean of each person's "
              "box bottom centres mapped through the homographies. No published tracking "
              "figure uses this protocol.\n\n")
    rows = []
    for ds, label in (("epfl", "**mvtrack**, annotated boxes as they are"),
                      ("epfl_default", "mvtrack, annotated boxes, default detector model")):
        for gate, suffix in (("1 m", "1m"), ("0.5 m", "05m")):
            rid = f"{ds}_{suffix}"
            m = R[rid]["metrics"]
            rows.append([label, "59-4887", gate, pct(m.get("mota")), pct(m.get("idf1")),
                         pct(m.get("hota")), m.get("ids"),
                         f"{m.get('pred_ids')} / {m.get('gt_ids')}", m.get("id_transfers"),
                         f"`{rid}`"])
    md.append(table(hdr, rows))

    md.append("\n### Commands\n\nFrom the repository root, with `R` the output directory "
              "(`build/results-run` by default) and `mvtrack` the built program on `PATH` "
              "(`$R/commands.sh` holds them all, runnable, in order).\n\n")
    md.append("Conversions:\n\n```sh\n")
    with open(os.path.join(out_dir, "commands.sh"), encoding="utf-8") as f:
        for line in f:
            if line.startswith(("mvtrack convert ", "mvtrack sim ", "cp ")):
                md.append(line)
    md.append("```\n\nRuns:\n\n")
    for rid, run in R.items():
        md.append(f"- `{rid}`:\n  ```sh\n")
        for cmd in run["commands"]:
            md.append(f"  {cmd}\n")
        md.append("  ```\n")
    for aid, a in A.items():
        md.append(f"- `{aid}` (the tracks of `{a['tracks_run']}`):\n  ```sh\n  {a['command']}\n"
                  "  ```\n")
    return "".join(md)


def floors(out_dir):
    """Bounds for tests/regression/floors.txt from R/results.json (margins as stated there)."""
    import math
    with open(os.path.join(out_dir, "results.json"), encoding="utf-8") as f:
        runs = json.load(f)["runs"]
    def floor(value, margin):
        return math.floor((value - margin) * 10000) / 10000

    lines = []
    for ds in ("shelf", "campus"):
        m = runs[ds]["metrics"]
        lines.append(f"{ds} pcp_average >= {floor(m['pcp_average'], 0.005):.4f}")
        for actor in ("0", "1", "2"):
            lines.append(f"{ds} pcp_actor{actor} >= {floor(m['pcp_actors'][actor], 0.005):.4f}")
        lines.append(f"{ds} mota >= {floor(m['mota'], 0.01):.4f}")
        lines.append(f"{ds} idf1 >= {floor(m['idf1'], 0.01):.4f}")
        lines.append(f"{ds} mpjpe_m <= {math.ceil((m['mpjpe_m'] + 0.002) * 10000) / 10000:.4f}")
        for key, name in (("fp", "false_positives"), ("fn", "misses"), ("ids", "id_switches")):
            lines.append(f"{ds} {name} <= {m[key] + max(2, math.ceil(0.1 * m[key]))}")
        # Identity coverage: no margin (no id may pass between actors; Shelf's actors keep one
        # id each).
        lines.append(f"{ds} id_transfers <= {m['id_transfers']}")
        if ds == "shelf":
            lines.append(f"{ds} id_fragmentations <= {m['id_fragmentations']}")
    # The skeleton fit (issue 40): PCP and MPJPE as above; bone-length CV (mean over tracks /
    # worst track) + 0.5 / + 1.0 percentage point.
    for ds, rid in (("shelf_fit", "shelf_refinement_fit_skeleton"),
                    ("campus_fit", "campus_refinement_fit_skeleton")):
        m = runs[rid]["metrics"]
        lines.append(f"{ds} pcp_average >= {floor(m['pcp_average'], 0.005):.4f}")
        for actor in ("0", "1", "2"):
            lines.append(f"{ds} pcp_actor{actor} >= {floor(m['pcp_actors'][actor], 0.005):.4f}")
        lines.append(f"{ds} mpjpe_m <= {math.ceil((m['mpjpe_m'] + 0.002) * 10000) / 10000:.4f}")
        lines.append(f"{ds} bone_cv_mean <= "
                     f"{math.ceil((m['bone_cv_mean'] + 0.005) * 10000) / 10000:.4f}")
        lines.append(f"{ds} bone_cv_worst_track <= "
                     f"{math.ceil((m['bone_cv_worst_track'] + 0.01) * 10000) / 10000:.4f}")
    m = runs["wildtrack"]["metrics"]
    lines.append(f"wildtrack modp_m <= {math.ceil((m['modp_m'] + 0.01) * 10000) / 10000:.4f}")
    for key in ("moda", "precision", "recall"):
        lines.append(f"wildtrack {key} >= {floor(m[key], 0.01):.4f}")
    return "\n".join(lines) + "\n"


def splice(generated_path, doc_path):
    with open(generated_path, encoding="utf-8") as f:
        generated = f.read()
    with open(doc_path, encoding="utf-8") as f:
        doc = f.read()
    if doc.count(BEGIN) != 1 or doc.count(END) != 1 or doc.index(BEGIN) > doc.index(END):
        sys.exit(f"results_tables.py: {doc_path}: needs exactly one pair of markers\n"
                 f"  {BEGIN}\n  {END}")
    head, rest = doc.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(doc_path, "w", encoding="utf-8") as f:
        f.write(head + BEGIN + "\n\n" + generated + "\n" + END + tail)


def block(text, path):
    """The text between README_BEGIN and README_END (exactly one pair) of `text`."""
    if text.count(README_BEGIN) != 1 or text.count(README_END) != 1:
        sys.exit(f"results_tables.py: {path}: needs exactly one pair of markers\n"
                 f"  {README_BEGIN}\n  {README_END}")
    return text.split(README_BEGIN, 1)[1].split(README_END, 1)[0]


def copy_readme_table(results_path, readme_path):
    """Copies the README table block of RESULTS.md into README.md."""
    with open(results_path, encoding="utf-8") as f:
        table_text = block(f.read(), results_path)
    with open(readme_path, encoding="utf-8") as f:
        readme = f.read()
    old = block(readme, readme_path)
    with open(readme_path, "w", encoding="utf-8") as f:
        f.write(readme.replace(README_BEGIN + old + README_END,
                               README_BEGIN + table_text + README_END, 1))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out")
    ap.add_argument("--commit", default="unknown")
    ap.add_argument("--dirty", default="?")
    ap.add_argument("--version", default="")
    ap.add_argument("--mvtrack", default="")
    ap.add_argument("--data", default="")
    ap.add_argument("--splice", nargs=2, metavar=("GENERATED_MD", "DOC"))
    ap.add_argument("--floors", metavar="R")
    ap.add_argument("--readme", nargs=2, metavar=("RESULTS_MD", "README_MD"),
                    help="copy RESULTS.md's README table into README.md")
    a = ap.parse_args()
    if a.readme:
        copy_readme_table(*a.readme)
        return
    if a.floors:
        sys.stdout.write(floors(a.floors))
        return
    if a.splice:
        splice(*a.splice)
        return
    if not a.out:
        ap.error("--out or --splice is required")
    runs = load(a.out)
    info = {"commit": a.commit, "dirty": a.dirty, "version": a.version.strip(),
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "mvtrack": a.mvtrack, "data": a.data}
    md = render(a.out, runs, info)
    with open(os.path.join(a.out, "results.md"), "w", encoding="utf-8") as f:
        f.write(md)
    doc = {"schema": "mvtrack.results/1", "generated": info, "runs": runs,
           "paper": {"table6_shelf": PAPER_T6_SHELF, "table6_campus": PAPER_T6_CAMPUS,
                     "table7": PAPER_T7, "table8": PAPER_T8, "table5": PAPER_T5}}
    with open(os.path.join(a.out, "results.json"), "w", encoding="utf-8") as f:
        json.dump(doc, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
