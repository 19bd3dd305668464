# mvtrack convert: help, usage errors (exit 2), failures without data (exit 1). No data needed.
source "$(dirname "$0")/common.sh"

expect_exit 0 "$OUT/help.txt" "$MVTRACK" convert --help
for f in shelf campus panoptic wildtrack jsonl; do
  expect_grep "^  $f " "$OUT/help.txt"
  expect_exit 0 "$OUT/help_$f.txt" "$MVTRACK" convert "$f" --help
  expect_grep "^usage: mvtrack convert $f --out DIR" "$OUT/help_$f.txt"
  expect_grep "^  --channel VALUE" "$OUT/help_$f.txt"
done
expect_grep "^  --clean" "$OUT/help_campus.txt"
expect_grep "noise-px" "$OUT/help_panoptic.txt"
expect_grep "^  --skip-bad-lines" "$OUT/help_jsonl.txt"
# The top-level command list names convert.
expect_exit 0 "$OUT/top.txt" "$MVTRACK" --help
expect_grep "^  convert " "$OUT/top.txt"

# Usage errors: exit status 2 with a message.
expect_exit 2 "$OUT/u1.txt" "$MVTRACK" convert
expect_exit 2 "$OUT/u2.txt" "$MVTRACK" convert nosuchformat --out "$OUT/x"
expect_grep "unknown format 'nosuchformat'" "$OUT/u2.txt"
expect_exit 2 "$OUT/u3.txt" "$MVTRACK" convert shelf
expect_grep "--out DIR is required" "$OUT/u3.txt"
expect_exit 2 "$OUT/u4.txt" "$MVTRACK" convert shelf --out "$OUT/x" --channel both
expect_grep "--channel must be" "$OUT/u4.txt"
expect_exit 2 "$OUT/u5.txt" "$MVTRACK" convert wildtrack --out "$OUT/x" --bogus
expect_grep "unknown option --bogus" "$OUT/u5.txt"
expect_exit 2 "$OUT/u6.txt" "$MVTRACK" convert campus --out "$OUT/x" --clean --seed 3
expect_grep "--corruption clean disables the corruption model; --seed" "$OUT/u6.txt"
expect_exit 2 "$OUT/u6a.txt" "$MVTRACK" convert shelf --out "$OUT/x" --peer 4d_assoc
expect_grep "--peer must be 4d_association or 4d_association_linux" "$OUT/u6a.txt"
expect_exit 2 "$OUT/u6b.txt" "$MVTRACK" convert campus --out "$OUT/x" --corruption harder
expect_grep "--corruption must be clean, default or hard" "$OUT/u6b.txt"
expect_exit 2 "$OUT/u6c.txt" "$MVTRACK" convert campus --out "$OUT/x" --clean --corruption hard
expect_grep "--clean contradicts --corruption hard" "$OUT/u6c.txt"
expect_exit 2 "$OUT/u6d.txt" "$MVTRACK" convert panoptic --out "$OUT/x" --sequence 160906_band1 --noise-tail-dof 40
expect_grep "--noise-tail-dof must be in 0-30" "$OUT/u6d.txt"
expect_exit 2 "$OUT/u7.txt" "$MVTRACK" convert campus --out "$OUT/x" --dropout 1.5
expect_grep "dropout" "$OUT/u7.txt"
expect_exit 2 "$OUT/u8.txt" "$MVTRACK" convert campus --out "$OUT/x" --seed -1
expect_exit 2 "$OUT/u9.txt" "$MVTRACK" convert panoptic --out "$OUT/x"
expect_grep "--sequence is required" "$OUT/u9.txt"
expect_exit 2 "$OUT/u10.txt" "$MVTRACK" convert panoptic --out "$OUT/x" --sequence 160906_band9
expect_grep "unknown sequence" "$OUT/u10.txt"
expect_exit 2 "$OUT/u11.txt" "$MVTRACK" convert panoptic --out "$OUT/x" --sequence 160906_band1 \
  --cameras 00_02 --num-cameras 3
expect_grep "either --cameras or --num-cameras" "$OUT/u11.txt"
expect_exit 2 "$OUT/u12.txt" "$MVTRACK" convert panoptic --out "$OUT/x" --sequence 160906_band1 --num-cameras 32
expect_exit 2 "$OUT/u13.txt" "$MVTRACK" convert panoptic --out "$OUT/x" --sequence 160906_band1 --cameras 00_02,,00_06
expect_grep "empty entry" "$OUT/u13.txt"
expect_exit 2 "$OUT/u14.txt" "$MVTRACK" convert panoptic --out "$OUT/x" --sequence 160906_band1 --cameras 00_02,2
expect_grep "listed twice" "$OUT/u14.txt"
expect_exit 2 "$OUT/u15.txt" "$MVTRACK" convert jsonl --out "$OUT/x" --calibration c.yaml
expect_grep "--detections FILE.jsonl is required" "$OUT/u15.txt"
[ ! -e "$OUT/x" ] || fail "a usage error created the output directory"

# A missing dataset: exit 1, naming the path and MVTRACK_DATA; nothing is written.
for f in shelf campus wildtrack; do
  expect_exit 1 "$OUT/m_$f.txt" "$MVTRACK" convert "$f" --data "$OUT/no_data" --out "$OUT/m_$f"
  expect_fixed "dataset directory $OUT/no_data/$f not found" "$OUT/m_$f.txt"
  expect_fixed "MVTRACK_DATA" "$OUT/m_$f.txt"
  [ ! -e "$OUT/m_$f" ] || fail "a failed conversion created $OUT/m_$f"
done
expect_exit 1 "$OUT/m_panoptic.txt" "$MVTRACK" convert panoptic --sequence 160906_band2 \
  --data "$OUT/no_data" --out "$OUT/m_p"
expect_fixed "$OUT/no_data/panoptic not found" "$OUT/m_panoptic.txt"
# $MVTRACK_DATA is the default data root.
expect_exit 1 "$OUT/env.txt" env MVTRACK_DATA="$OUT/env_root" "$MVTRACK" convert shelf --out "$OUT/e"
expect_fixed "dataset directory $OUT/env_root/shelf not found" "$OUT/env.txt"
echo "help: ok"
