#!/usr/bin/env bash
# Regenerates every figure of docs/RESULTS.md in one command: converts the datasets of
# ../shared/data (or $MVTRACK_DATA), replays each experiment with `mvtrack replay`, scores it
# with `mvtrack eval --json`, and writes the tables (markdown + JSON) with
# tools/dev/results_tables.py.
#
# Usage: tools/dev/results.sh [--build] [--mvtrack PATH] [--out DIR] [--data DIR]
#                             [--update-docs] [--help]
#   --build        build the `mvtrack` target of the release preset first (build/release)
#   --mvtrack P    the mvtrack program (default: build/release/tools/mvtrack)
#   --out DIR      work and output directory (default: build/results-run); replaced entirely
#                  (refused when it exists, is not empty and holds no earlier manifest.tsv)
#   --data DIR     dataset root (default: $MVTRACK_DATA, else ../shared/data)
#   --update-docs  replace the generated part of docs/RESULTS.md (between its markers) and
#                  README.md's results table (copied from it; CTest docs/readme_results)
#
# Every command is run from the repository root exactly as it is recorded: $R stands for the
# output directory and `mvtrack` for the chosen program (its directory is put first on PATH).
# Output: DIR/results.md, DIR/results.json, DIR/commands.sh (every command, runnable),
# DIR/manifest.tsv, DIR/runs/*.eval.json, DIR/runs/*.jsonl and logs.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD

usage() { sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'; }
build=0
update_docs=0
mvtrack_bin=build/release/tools/mvtrack
out=build/results-run
data=${MVTRACK_DATA:-$root/../shared/data}
while [[ $# -gt 0 ]]; do
  case $1 in
    --build) build=1 ;;
    --update-docs) update_docs=1 ;;
    --mvtrack) mvtrack_bin=${2:?--mvtrack needs a path}; shift ;;
    --out) out=${2:?--out needs a directory}; shift ;;
    --data) data=${2:?--data needs a directory}; shift ;;
    --help | -h) usage; exit 0 ;;
    *) echo "results.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

if [[ $build == 1 ]]; then
  export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=true
  cmake --preset release >/dev/null
  cmake --build --preset release --target mvtrack
fi
if [[ ! -x $mvtrack_bin ]]; then
  echo "results.sh: $mvtrack_bin: no such program (build it, or pass --build or --mvtrack PATH)" >&2
  exit 1
fi
for d in shelf campus panoptic wildtrack epfl; do
  if [[ ! -d $data/$d ]]; then
    echo "results.sh: $data/$d: dataset missing (set --data or MVTRACK_DATA)" >&2
    exit 1
  fi
done
command -v python3 >/dev/null || { echo "results.sh: python3 is required" >&2; exit 1; }

mvtrack_dir=$(cd "$(dirname "$mvtrack_bin")" && pwd)
export PATH="$mvtrack_dir:$PATH"
export MVTRACK_DATA=$data
R=$out
if [[ -d $R && -n $(ls -A "$R") && ! -f $R/manifest.tsv ]]; then
  echo "results.sh: $R exists, is not empty and is not an earlier results directory: not" \
    "replacing it (choose another --out)" >&2
  exit 1
fi
rm -rf "$R"
mkdir -p "$R/runs"
manifest=$R/manifest.tsv
commands=$R/commands.sh
printf 'id\tdataset\tconfig\tcommands\teval_json\treplay_log\n' >"$manifest"
{
  echo "#!/usr/bin/env bash"
  echo "# Every command tools/dev/results.sh ran, in order (from the repository root)."
  echo "set -euo pipefail"
  echo "R=$R"
} >"$commands"

step=0
progress() { step=$((step + 1)); echo "results: [$step] $*" >&2; }
trap 'echo "results.sh: step $step failed; its command is the last line of $commands" >&2' ERR

# Runs a recorded command line (with $R unexpanded in the record).
run() {
  local cmd=$1
  echo "$cmd" >>"$commands"
  eval "$cmd"
}

# convert NAME ARGS...: mvtrack convert into $R/NAME.
convert() {
  local name=$1
  shift
  progress "convert $name"
  run "mvtrack convert $* --out \$R/$name --quiet"
}

# experiment ID DATASET_DIR MODE LAYOUT CONFIG EVAL_ARGS...
#   replays $R/DATASET_DIR with CONFIG ('-' = defaults) and scores it against its ground truth.
experiment() {
  local id=$1 ds=$2 mode=$3 layout=$4 config=$5
  shift 5
  local cfg_arg=""
  [[ $config != - ]] && cfg_arg=" --config $config"
  local gt=ground_truth.jsonl
  local replay="mvtrack replay --calibration \$R/$ds/calibration.yaml --mode $mode --layout $layout$cfg_arg --jsonl \$R/runs/$id.jsonl --quiet \$R/$ds/detections.lcmlog"
  local ev="mvtrack eval --gt \$R/$ds/$gt \$R/runs/$id.jsonl $* --json \$R/runs/$id.eval.json"
  progress "$id"
  echo "$replay > \$R/runs/$id.replay.txt 2>&1" >>"$commands"
  eval "$replay" >"$R/runs/$id.replay.txt" 2>&1
  run "$ev > \$R/runs/$id.eval.txt"
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$id" "$ds" "$config" "$replay && $ev" \
    "runs/$id.eval.json" "runs/$id.replay.txt" >>"$manifest"
}

# peer ID DATASET_DIR FILE EVAL_ARGS...: scores a file of the converted dataset that is not our
# output (a peer's published output, peer.jsonl; WILDTRACK's input points) with our evaluator.
peer() {
  local id=$1 ds=$2 file=$3
  shift 3
  local ev="mvtrack eval --gt \$R/$ds/ground_truth.jsonl \$R/$ds/$file $* --json \$R/runs/$id.eval.json"
  progress "$id"
  run "$ev > \$R/runs/$id.eval.txt"
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$id" "$ds" "-" "$ev" "runs/$id.eval.json" "-" >>"$manifest"
}

ab=docs/examples/ablations
# Shelf: head_top of our BODY25 output by 4D Association's MappingToShelf, the rule its peer
# output is mapped with and the protocol of its published Shelf numbers (docs/RESULTS.md).
shelf_eval="--frames 300-600 --distance joints --pcp --actors 0,1,2 --head-rule shelf-4da"
campus_eval="--frames 350-470,650-750 --distance joints --pcp --actors 0,1,2"
panoptic_eval="--distance joints --pcp"
wildtrack_eval="--points --area -3,9,-9,27"

# ---- Datasets.
convert shelf shelf
convert shelf_4da_linux shelf --peer 4d_association_linux
convert campus campus
convert campus_clean campus --clean
convert campus_hard campus --corruption hard
for seed in 2 3 4 5 6 7 8 9 10; do convert "campus_hard_s$seed" campus --corruption hard --seed $seed; done
for seq in 160906_band1 160906_band2; do
  for n in 5 10 31; do convert "panoptic_${seq#160906_}_c$n" panoptic --sequence $seq --num-cameras $n; done
done
convert wildtrack wildtrack
convert wildtrack_annotated wildtrack --detections annotated --corruption clean
convert wildtrack_annotated_all wildtrack --detections annotated --corruption clean --frames 0-399
convert wildtrack_annotated_all_default wildtrack --detections annotated --corruption default \
  --frames 0-399
convert wildtrack_mvdetr_miss20 wildtrack --corruption default --noise-px 0 --false-positives 0 \
  --miss-rate 0.2
convert epfl epfl --corruption clean
convert epfl_default epfl --corruption default

# ---- Main results (paper Table 6) and the peers' own outputs.
experiment shelf shelf poses body25 - $shelf_eval
experiment shelf_head_campus shelf poses body25 - --frames 300-600 --distance joints --pcp \
  --actors 0,1,2 --head-rule campus
peer shelf_peer_4da shelf peer.jsonl $shelf_eval
peer shelf_peer_4da_linux shelf_4da_linux peer.jsonl $shelf_eval
experiment campus campus poses shelf14 - $campus_eval
experiment campus_clean campus_clean poses shelf14 - $campus_eval
experiment campus_hard campus_hard poses shelf14 - $campus_eval
peer campus_peer_crossview campus peer.jsonl $campus_eval

# ---- Ablations on Shelf and Campus: association (Table 5 / appendix), triangulation (Table 7),
# the nu, delta, lambda grid (Table 8).
for ds in shelf campus; do
  if [[ $ds == shelf ]]; then layout=body25; ev=$shelf_eval; else layout=shelf14; ev=$campus_eval; fi
  for v in association_complete_linkage_empty_as_zero association_complete_linkage_empty_as_upper \
           association_single_linkage_empty_as_upper triangulation_dlt triangulation_ransac \
           window_nu30_delta20_lambda0.3 window_nu50_delta30_lambda0.3 \
           window_nu70_delta50_lambda0.3 window_nu50_delta30_lambda0.1 \
           window_nu50_delta30_lambda0.6; do
    experiment "${ds}_$v" $ds poses $layout $ab/$v.yaml $ev
  done
done

# ---- Campus hard corruption, seeds 2-10 (campus_hard is seed 1).
for seed in 2 3 4 5 6 7 8 9 10; do
  experiment "campus_hard_s$seed" "campus_hard_s$seed" poses shelf14 - $campus_eval
done

# ---- Ablations of the multi-frame stages (issue 17) on Shelf, Campus (default, hard seeds
# 1-10) and Panoptic (5 and 10 cameras).
for v in refinement_no_smoothing refinement_smooth_every_joint refinement_fit_skeleton \
         linking_no_gap_bridging \
         linking_no_duplicate_detection; do
  experiment "shelf_$v" shelf poses body25 $ab/$v.yaml $shelf_eval
  experiment "campus_$v" campus poses shelf14 $ab/$v.yaml $campus_eval
  experiment "campus_hard_$v" campus_hard poses shelf14 $ab/$v.yaml $campus_eval
  for seed in 2 3 4 5 6 7 8 9 10; do
    experiment "campus_hard_s${seed}_$v" "campus_hard_s$seed" poses shelf14 $ab/$v.yaml $campus_eval
  done
  for seq in band1 band2; do
    for n in 5 10; do
      experiment "panoptic_${seq}_c${n}_$v" "panoptic_${seq}_c$n" poses panoptic19 $ab/$v.yaml \
        $panoptic_eval
    done
  done
done

# ---- Panoptic, 5 / 10 / 31 cameras.
for seq in band1 band2; do
  for n in 5 10 31; do
    experiment "panoptic_${seq}_c$n" "panoptic_${seq}_c$n" poses panoptic19 - $panoptic_eval
  done
done

# ---- WILDTRACK footprints against its ground-truth positions (MODA, MODP, precision, recall),
# next to the tracker's input (MVDeTr's ground points) scored the same way.
peer wildtrack_input_mvdetr wildtrack ground_points.jsonl $wildtrack_eval
experiment wildtrack wildtrack boxes none - $wildtrack_eval
for v in box_point_center box_point_bottom_center frame_counts_at_any_rate \
         association_complete_linkage_empty_as_zero association_complete_linkage_empty_as_upper; do
  experiment "wildtrack_$v" wildtrack boxes none $ab/$v.yaml $wildtrack_eval
done

# ---- WILDTRACK tracking with person ids (opentraj/), 1 m (the literature's radius) and 0.5 m;
# MVDeTr's boxes with 20 % removed against the ground points of the kept boxes (MODA, 0.5 m).
for ds in wildtrack wildtrack_annotated wildtrack_annotated_all wildtrack_annotated_all_default; do
  experiment "${ds}_tracking_1m" $ds boxes none - --threshold 1.0
  experiment "${ds}_tracking_05m" $ds boxes none - --threshold 0.5
done
peer wildtrack_mvdetr_miss20_input wildtrack_mvdetr_miss20 ground_points.jsonl $wildtrack_eval
experiment wildtrack_mvdetr_miss20 wildtrack_mvdetr_miss20 boxes none - $wildtrack_eval

# ---- EPFL Terrace (cameras from the floor homographies), the whole sequence.
for ds in epfl epfl_default; do
  experiment "${ds}_1m" $ds boxes none - --threshold 1.0
  experiment "${ds}_05m" $ds boxes none - --threshold 0.5
done

# ---- Analytics (issue 41): region visits and line crossings of the tracks against those of the
# ground truth's tracks under the same rules (`mvtrack analytics --gt`), on the simulator's
# enter/leave scene (9000 frames, boxes and poses) and on WILDTRACK with person ids.
printf 'id\ttracks_run\tsite\tcommand\tjson\n' >"$R/analytics.tsv"
# sim_scene NAME ARGS...: mvtrack sim into $R/NAME, its ground truth where experiment() reads it.
sim_scene() {
  local name=$1
  shift
  progress "sim $name"
  run "mvtrack sim $* --out \$R/$name --quiet"
  run "cp \$R/$name/gt.jsonl \$R/$name/ground_truth.jsonl"
}
# analytics_run ID TRACKS_RUN DATASET_DIR SITE: the analytics of runs/TRACKS_RUN.jsonl.
analytics_run() {
  local id=$1 tracks=$2 ds=$3 site=$4
  local cmd="mvtrack analytics --tracks \$R/runs/$tracks.jsonl --regions $site --gt \$R/$ds/ground_truth.jsonl --quiet --json \$R/runs/$id.analytics.json"
  progress "$id"
  run "$cmd > \$R/runs/$id.analytics.txt"
  printf '%s\t%s\t%s\t%s\t%s\n' "$id" "$tracks" "$site" "$cmd" "runs/$id.analytics.json" \
    >>"$R/analytics.tsv"
}
sim_scene sim_enter_leave_boxes --cameras 4 --people 12 --enter-leave --frames 9000 --seed 11 \
  --mode boxes
sim_scene sim_enter_leave_poses --cameras 4 --people 12 --enter-leave --frames 9000 --seed 11 \
  --mode poses
experiment sim_enter_leave_boxes sim_enter_leave_boxes boxes none - --threshold 0.5
experiment sim_enter_leave_poses sim_enter_leave_poses poses coco17 - --threshold 0.5
for mode in boxes poses; do
  analytics_run "analytics_sim_enter_leave_$mode" "sim_enter_leave_$mode" \
    "sim_enter_leave_$mode" docs/examples/sites/sim_enter_leave.yaml
done
# The same room with four places where people stand for minutes (mean 2 min, shifting within
# 0.2 m), each on the border of a region or on a line of the site file; its analytics with the
# default rules and with none (band 0, hold 0: what the rules prevent).
linger_spots="2.5,3.5;4.5,3;3.5,4.5;1.5,5"
for mode in boxes poses; do
  sim_scene "sim_linger_$mode" --cameras 4 --people 12 --enter-leave --frames 9000 --seed 11 \
    --mode $mode --linger-at "'$linger_spots'"
done
experiment sim_linger_boxes sim_linger_boxes boxes none - --threshold 0.5
experiment sim_linger_poses sim_linger_poses poses coco17 - --threshold 0.5
run "{ cat docs/examples/sites/sim_enter_leave.yaml; printf 'rules:\\n  hysteresis_m: 0\\n  hold_s: 0\\n'; } > \$R/sim_linger_no_rules.yaml"
for mode in boxes poses; do
  analytics_run "analytics_sim_linger_$mode" "sim_linger_$mode" "sim_linger_$mode" \
    docs/examples/sites/sim_enter_leave.yaml
  analytics_run "analytics_sim_linger_${mode}_no_rules" "sim_linger_$mode" "sim_linger_$mode" \
    "\$R/sim_linger_no_rules.yaml"
done
analytics_run analytics_wildtrack_annotated_all wildtrack_annotated_all_tracking_1m \
  wildtrack_annotated_all docs/examples/sites/wildtrack.yaml
analytics_run analytics_wildtrack_annotated_all_default wildtrack_annotated_all_default_tracking_1m \
  wildtrack_annotated_all_default docs/examples/sites/wildtrack.yaml

# ---- Tables.
progress "tables"
commit=$(git rev-parse HEAD 2>/dev/null || echo unknown)
dirty=$(git status --porcelain 2>/dev/null | grep -c . || true)
version=$(mvtrack --version 2>/dev/null || echo "")
python3 tools/dev/results_tables.py --out "$R" --commit "$commit" --dirty "$dirty" \
  --version "$version" --mvtrack "$mvtrack_bin" --data "$data"
if [[ $update_docs == 1 ]]; then
  python3 tools/dev/results_tables.py --splice "$R/results.md" docs/RESULTS.md
  python3 tools/dev/results_tables.py --readme docs/RESULTS.md README.md
fi
echo "results: wrote $R/results.md and $R/results.json ($step steps)" >&2
