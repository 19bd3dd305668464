# Sourced by the tests/python scripts: ensure_venv VENV_DIR PYTHON WHEEL makes VENV_DIR a
# virtualenv with PyPI's lcm (pinned) and the mvtrack-lcmtypes wheel of this build, created once
# and cached in the build tree (later runs reinstall the wheel only when it changed, offline).
# When PyPI cannot be reached: fail under CI=true, otherwise print SKIPPED and exit 77 (CTest's
# skip code).

# The PyPI lcm release the examples are tested with (../shared/TOOLCHAIN.md).
MVTRACK_PYPI_LCM="lcm==1.5.3"

ensure_venv() {
  local venv=$1 python=$2 wheel=$3
  [ -f "$wheel" ] || fail "wheel $wheel not found (build the target mvtrack_lcmtypes_python_dist)"
  mkdir -p "$(dirname "$venv")"
  # One creator at a time: tests may run in parallel.
  exec 9>"$venv.lock"
  flock 9
  if ! "$venv/bin/python" -c "import lcm" >/dev/null 2>&1; then
    rm -rf "$venv"
    "$python" -m venv "$venv" >"$venv.log" 2>&1 ||
      { cat "$venv.log" >&2; fail "'$python -m venv' failed (Debian: apt-get install python3-venv)"; }
    if ! "$venv/bin/pip" install --disable-pip-version-check --timeout 20 --retries 1 \
        "$MVTRACK_PYPI_LCM" >>"$venv.log" 2>&1; then
      rm -rf "$venv"
      local why="pip could not install $MVTRACK_PYPI_LCM from PyPI (log: $venv.log)"
      if [ "${CI:-}" = true ] || [ "${CI:-}" = 1 ]; then
        cat "$venv.log" >&2
        fail "CI is set and $why; CI needs access to https://pypi.org"
      fi
      echo "SKIPPED: $why"
      exit 77
    fi
  fi
  # The wheel only when it changed: reinstalling it while a parallel test imports the package
  # makes that test see a half-installed package.
  if ! cmp -s "$wheel" "$venv/installed.whl"; then
    "$venv/bin/pip" install --disable-pip-version-check --no-index --no-deps --force-reinstall \
      --quiet "$wheel" >>"$venv.log" 2>&1 || { cat "$venv.log" >&2; fail "pip install $wheel failed"; }
    cp "$wheel" "$venv/installed.whl"
  fi
  flock -u 9
}
