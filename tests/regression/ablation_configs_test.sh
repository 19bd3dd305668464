#!/usr/bin/env bash
# Every tracker options file of docs/examples/ablations (the variants tools/dev/results.sh runs)
# passes `mvtrack check-config`, and its effective options are the defaults with exactly the
# keys the file sets replaced by the values it gives ("the defaults with only these keys
# changed", as each file's header says).
# Usage: ablation_configs_test.sh MVTRACK SOURCE_DIR
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: $0 MVTRACK SOURCE_DIR" >&2
  exit 2
fi
MVTRACK=$1
SRC=$2
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

printf 'tracker: {}\n' >"$WORK/defaults.yaml"
"$MVTRACK" check-config "$WORK/defaults.yaml" >"$WORK/defaults.out"
n=0
for f in "$SRC"/docs/examples/ablations/*.yaml; do
  n=$((n + 1))
  expect_exit 0 "$WORK/$n.out" "$MVTRACK" check-config "$f"
  printf '%s\t%s\n' "$f" "$WORK/$n.out" >>"$WORK/list.tsv"
done
[ "$n" -ge 10 ] || fail "expected at least 10 ablation files, found $n"
python3 - "$WORK/defaults.out" "$WORK/list.tsv" <<'PY'
import sys

def flat(path):
    """'section.key' -> value of a two-level `tracker:` YAML map (comments stripped)."""
    out, section = {}, None
    for raw in open(path, encoding="utf-8"):
        line = raw.split("#", 1)[0].rstrip()
        if not line.strip() or line.strip() == "tracker:":
            continue
        indent = len(line) - len(line.lstrip())
        key, _, value = line.strip().partition(":")
        value = value.strip()
        if indent == 2 and not value:
            section = key
            continue
        out[(section + "." if indent > 2 else "") + key] = value
    return out

def same(a, b):
    try:
        return float(a) == float(b)
    except ValueError:
        return a == b

defaults = flat(sys.argv[1])
for entry in open(sys.argv[2], encoding="utf-8"):
    name, effective_path = entry.rstrip("\n").split("\t")
    effective, wanted = flat(effective_path), flat(name)
    assert wanted, f"{name}: sets no option"
    assert set(effective) == set(defaults), f"{name}: the effective options have other keys"
    for k in wanted:
        assert k in effective, f"{name}: {k} is not an option"
    # Effective = the defaults with exactly the file's keys replaced by the file's values.
    for k, v in effective.items():
        want = wanted.get(k, defaults[k])
        assert same(v, want), f"{name}: {k} is {v}, expected {want}"
PY
echo "PASS: $n ablation option files"
