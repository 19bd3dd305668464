#!/usr/bin/env bash
# mvtrack eval --pcp / --layout / --distance joints / --frames / --actors, and box-mode tracks:
# PCP above the floor 0.95 (measured 0.9997 in shelf14), the layout mapping printed, the
# Shelf/Campus parts used in shelf14 and the layout's bones otherwise, frame and actor selection
# applied, and PCP refused for tracks without joints (box-mode MOTA floor 0.95, measured 0.989).
source "$(dirname "$0")/common.sh"
P=$WORK/poses
B=$WORK/boxes
GT=$P/gt.jsonl

expect_exit 0 "$OUT/replay.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode poses --out "$OUT/tracks.lcmlog" --jsonl "$OUT/tracks.jsonl" "$P/detections.lcmlog"

# PCP: in shelf14 both sides are mapped (and the mapping is printed); in coco17 every bone.
expect_exit 0 "$OUT/pcp.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" --layout shelf14 \
  --distance joints --pcp --json "$OUT/pcp.json"
expect_grep "predictions mapped coco17 -> shelf14 \(core::MakeKeypointMapping\)" "$OUT/pcp.txt"
expect_grep "head_top +<- .*l_ear" "$OUT/pcp.txt"
expect_grep "^PCP \(alpha 0.50" "$OUT/pcp.txt"
json_assert "$OUT/pcp.json" \
  '"torso" in d["pcp"]["bone_names"]' "Shelf/Campus parts not used" \
  'd["tracking"]["distance"] == "mean_joint"' "--distance joints ignored" \
  'd["pcp"]["average_pcp"] >= 0.95' "PCP below the floor 0.95"
pcp=$(json_get "$OUT/pcp.json" 'd["pcp"]["average_pcp"]')
# --head-rule shelf-4da: head_top of both mapped sides by 4D Association's rule, stated in the
# mapping and in the PCP protocol; the other parts are unchanged; an unknown rule is a usage error.
expect_exit 0 "$OUT/pcp4da.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" --layout shelf14 \
  --distance joints --pcp --head-rule shelf-4da --json "$OUT/pcp4da.json"
expect_grep "head_top +<- instead \(--head-rule shelf-4da" "$OUT/pcp4da.txt"
json_assert "$OUT/pcp4da.json" \
  '"shelf-4da" in d["pcp"]["protocol"]' "head rule missing from the PCP protocol" \
  'd["pcp"]["average_pcp"] >= 0.95' "PCP with the 4D Association head rule below the floor 0.95"
python3 - "$OUT/pcp.json" "$OUT/pcp4da.json" <<'PY' || fail "--head-rule changed parts other than the head"
import json, sys
a, b = (json.load(open(p))["pcp"] for p in sys.argv[1:])
head = a["group_names"].index("head")
for x, y in zip(a["actors"], b["actors"]):
    for g, (u, v) in enumerate(zip(x["group_pcp"], y["group_pcp"])):
        if g != head and u != v:
            sys.exit(f"group {a['group_names'][g]}: {u} != {v}")
PY
expect_exit 2 "$OUT/badrule.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" --pcp \
  --head-rule 4da
expect_grep "head-rule must be 'campus' or 'shelf-4da'" "$OUT/badrule.txt"
expect_exit 0 "$OUT/pcp17.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" --pcp \
  --frames 0-99,200-239 --actors 0,1 --json "$OUT/pcp17.json"
json_assert "$OUT/pcp17.json" \
  'len(d["pcp"]["bone_names"]) > 0 and all("-" in n for n in d["pcp"]["bone_names"])' "coco17 PCP does not score the layout's bones" \
  'd["pcp"]["group_names"] == []' "layout protocol has no groups" \
  '[a["actor_id"] for a in d["pcp"]["actors"]] == [0, 1]' "--actors" \
  'd["tracking"]["clear_mot"]["num_frames"] == 140' "--frames" \
  'all(a["num_frames"] == 140 for a in d["pcp"]["actors"])' "--frames in PCP"

# Box-mode tracks: footprints only; PCP is refused.
expect_exit 0 "$OUT/breplay.log" "$MVTRACK" replay --quiet --calibration "$B/calibration.yaml" \
  --jsonl "$OUT/boxes.jsonl" "$B/detections.lcmlog"
expect_exit 0 "$OUT/bx.txt" "$MVTRACK" eval --gt "$B/gt.jsonl" --pred "$OUT/boxes.jsonl" --json "$OUT/bx.json"
expect_grep "joints: not compared" "$OUT/bx.txt"
json_assert "$OUT/bx.json" 'd["tracking"]["clear_mot"]["mota"] >= 0.95' "box-mode MOTA below the floor 0.95"
bmota=$(json_get "$OUT/bx.json" 'd["tracking"]["clear_mot"]["mota"]')
expect_exit 1 "$OUT/bxpcp.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/boxes.jsonl" --pcp
expect_grep "no joints in the predictions" "$OUT/bxpcp.txt"

echo "ok (PCP $pcp; boxes MOTA $bmota)"
