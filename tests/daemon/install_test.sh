#!/usr/bin/env bash
# The daemon's install rules (daemon/CMakeLists.txt), staged with DESTDIR: the binary, the
# systemd unit with this prefix's paths, the example configuration next to its calibration
# (valid as installed), and the documentation.
#   install_test.sh CMAKE DAEMON_BUILD_DIR PREFIX SYSCONFDIR OUT_DIR MVTRACK
set -euo pipefail
CMAKE=$1; BUILD=$2; PREFIX=$3; SYSCONF=$4; OUT=$5; MVTRACK=$6
. "$(dirname "$0")/../support/shell_asserts.sh"
rm -rf "$OUT"
mkdir -p "$OUT"
DESTDIR="$OUT/root" "$CMAKE" -P "$BUILD/cmake_install.cmake" > "$OUT/install.log"
R=$OUT/root
for f in "$PREFIX/bin/mvtrackd" "$PREFIX/lib/systemd/system/mvtrackd.service" \
         "$SYSCONF/mvtrack/mvtrackd.yaml" "$SYSCONF/mvtrack/calibration.example.yaml"; do
  [ -f "$R$f" ] || fail "not installed: $f"
done
[ -x "$R$PREFIX/bin/mvtrackd" ] || fail "mvtrackd is not executable"
expect_exit 0 "$OUT/version.log" "$R$PREFIX/bin/mvtrackd" --version
expect_grep "^mvtrackd " "$OUT/version.log"
U=$R$PREFIX/lib/systemd/system/mvtrackd.service
expect_grep "^ExecStart=$PREFIX/bin/mvtrackd --config $SYSCONF/mvtrack/mvtrackd.yaml$" "$U"
expect_grep "^Type=notify$" "$U"
expect_grep "^WatchdogSec=" "$U"
expect_grep "^DynamicUser=yes$" "$U"
expect_grep "^NoNewPrivileges=yes$" "$U"
expect_grep "^ProtectSystem=strict$" "$U"
expect_grep "^RestrictAddressFamilies=AF_INET AF_UNIX$" "$U"
# Reload without procps (tests/daemon/unit_reload_test.sh runs it).
expect_grep "^ExecReload=/bin/sh -c 'kill -HUP \\\$MAINPID'$" "$U"
# The installed configuration is valid where it lies (its calibration is found next to it).
expect_exit 0 "$OUT/check.log" "$MVTRACK" check-config "$R$SYSCONF/mvtrack/mvtrackd.yaml"
if command -v systemd-analyze > /dev/null; then
  sed "s|^ExecStart=.*|ExecStart=/bin/true|" "$U" > "$OUT/verify.service"
  # --man=no: Documentation= names mvtrackd(8), which is only installed with the package
  # (tests/package checks the page).
  systemd-analyze verify --man=no "$OUT/verify.service" > "$OUT/verify.log" 2>&1 ||
    { cat "$OUT/verify.log" >&2; fail "systemd-analyze verify rejects the unit"; }
fi
echo "ok"
