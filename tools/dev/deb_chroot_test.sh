#!/usr/bin/env bash
# Installs the Debian packages into a fresh Debian 12 and checks what an administrator would:
# debootstraps bookworm (variant minbase: Essential and Priority: required packages plus apt, so
# no procps, no systemd, no man-db, no python3) into a temporary directory, then in a chroot
#   1. apt-get install ./mvtrackd_*.deb: new packages and installed size (MiB, the sum of their
#      Installed-Size; apt prints decimal MB) (target: < 60 MB, no
#      Java, no OpenCV), the postinst's note, the conffiles, mvtrackd --version;
#   2. the unit's ExecReload= command, run as systemd would (MAINPID set, no PATH) against a
#      running mvtrackd: it must reload it with nothing but the minimal system (no procps);
#   3. man mvtrackd (man-db installed for that, after the measurement) and man -l of the page;
#   4. apt-get install ./mvtrack-tools_*.deb (new packages and size on top of the above), the
#      project's demo there
#      (tools/dev/demo.sh's run: mvtrackd on examples/demo/detections.lcmlog, mvtrack eval
#      against its ground truth; plus `mvtrack demo` and `mvtrack view`, which runs
#      mvtrack-pictures and OpenCV);
#   5. python3-mvtrack-lcmtypes: install, import with Debian's python3 and decode, purge
#      (no byte-code left behind);
#   6. remove and purge mvtrackd: the maintainer scripts run without error, remove keeps the
#      conffiles, purge leaves nothing (deb-systemd-helper state, /etc/mvtrack);
# and prints a summary table. Not run by CI: it downloads about 300 MB from the Debian mirror.
# Needs root, debootstrap and about 2 GB in TMPDIR. Mounts (proc, sys, dev, dev/pts) are undone
# on every exit.
#
# Usage: tools/dev/deb_chroot_test.sh [options]
#   --build DIR     build tree to run cpack in (default build/package: the package preset,
#                   configured with -DCMAKE_INSTALL_PREFIX=/usr, and built)
#   --debs DIR      use the .debs already in DIR instead of running cpack
#   --mirror URL    Debian mirror (default http://deb.debian.org/debian)
#   --tarball FILE  reuse the debootstrap download: FILE is made on the first run
#                   (debootstrap --make-tarball) and unpacked on later ones
#   --with-spy      also install mvtrack-spy (downloads a Java runtime, about 200 MB more)
#   --upgrade-from DEB  at the end, install DEB (the single package mvtrack_0.2.0_<arch>.deb of
#                   earlier builds; downloads about 850 MB) and upgrade it to these packages
#                   (apt-get install ./mvtrack_*.deb ./mvtrackd_*.deb ...: Breaks/Replaces)
#   --keep          keep the chroot directory (printed at the end)
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)

build=$repo/build/package
debs_dir=""
mirror=http://deb.debian.org/debian
tarball=""
with_spy=0
upgrade_from=""
keep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$(readlink -f "$2"); shift ;;
    --debs) debs_dir=$(readlink -f "$2"); shift ;;
    --mirror) mirror=$2; shift ;;
    --tarball) tarball=$(readlink -f "$2"); shift ;;
    --with-spy) with_spy=1 ;;
    --upgrade-from) upgrade_from=$(readlink -f "$2"); shift ;;
    --keep) keep=1 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "deb_chroot_test: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
cd "$repo"

name=deb_chroot_test
# shellcheck source=chroot_lib.sh
. "$repo/tools/dev/chroot_lib.sh"
chroot_start

# The packages.
mkdir -p "$work/debs"
if [ -n "$debs_dir" ]; then
  cp "$debs_dir"/*.deb "$work/debs/" || die "no .deb in $debs_dir"
else
  [ -f "$build/CMakeCache.txt" ] || die "$build is not a build tree (configure and build it, or pass --debs)"
  prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$build/CMakeCache.txt")
  [ "$prefix" = /usr ] ||
    die "$build installs under '$prefix': configure it with -DCMAKE_INSTALL_PREFIX=/usr"
  echo "== cpack -G DEB in $build"
  (cd "$build" && cpack -G DEB -B "$work/cpack") >"$work/cpack.log" 2>&1 ||
    { cat "$work/cpack.log" >&2; die "cpack failed (is $build built?)"; }
  cp "$work/cpack"/*.deb "$work/debs/"
fi
ls "$work/debs"
deb_of() {
  local f
  f=$(ls "$work/debs/$1"_*.deb 2>/dev/null | head -1)
  [ -n "$f" ] || die "no $1_*.deb among the packages"
  basename "$f"
}
deb_daemon=$(deb_of mvtrackd)
deb_tools=$(deb_of mvtrack-tools)
deb_python=$(deb_of python3-mvtrack-lcmtypes)

# A fresh Debian 12.
chroot_debootstrap "$mirror" "$tarball"
cp -r "$work/debs" "$root/tmp/debs"

in_root apt-get update -qq >"$work/apt-update.log" 2>&1 ||
  { cat "$work/apt-update.log" >&2; die "apt-get update failed in the chroot"; }

# norec_estimate DEB: "count MB" that `apt-get install --no-install-recommends ./DEB` would add
# (simulated; sizes from the archive's and the .deb's Installed-Size).
norec_estimate() {
  local deb=$1 own pkg
  own=$(dpkg-deb -f "$work/debs/$deb" Package)
  in_root apt-get install -s --no-install-recommends "/tmp/debs/$deb" >"$work/sim-$own.txt" 2>&1 || true
  for pkg in $(awk '/^Inst / { print $2 }' "$work/sim-$own.txt"); do
    if [ "$pkg" = "$own" ]; then dpkg-deb -f "$work/debs/$deb" Installed-Size
    else in_root apt-cache show --no-all-versions "$pkg" | sed -n 's/^Installed-Size: //p' | head -1
    fi
  done | awk '{ n++; kb += $1 } END { printf "%d %.1f\n", n, kb / 1024 }'
}

declare -A result
check() {  # check NAME OK-TEXT COMMAND...: records ok/FAIL for the summary, never exits
  local name=$1 text=$2
  shift 2
  if "$@"; then result[$name]="ok: $text"; else result[$name]="FAIL: $text"; failed=1; fi
}
failed=0

# 1. mvtrackd alone.
echo
echo "== apt-get install ./$deb_daemon"
snapshot "$work/before.txt"
# For comparison: what apt would add without the Recommends of the dependencies (glib's pull in
# shared-mime-info, libxml2 and libicu72), by the archive's Installed-Size.
read -r norec_n norec_mb < <(norec_estimate "$deb_daemon")
in_root apt-get install -y "/tmp/debs/$deb_daemon" 2>&1 | tee "$work/install-daemon.log"
[ "${PIPESTATUS[0]}" -eq 0 ] || die "apt-get install ./$deb_daemon failed"
snapshot "$work/after-daemon.txt"
read -r daemon_n daemon_mb < <(new_packages "$work/before.txt" "$work/after-daemon.txt")
join -v2 -t$'\t' "$work/before.txt" "$work/after-daemon.txt" | awk -F'\t' '{ printf "  %-32s %6d kB\n", $1, $2 }'
apt_says=$(sed -n 's/^After this operation, \(.*\) of additional disk space will be used\./\1/p' "$work/install-daemon.log")
echo "mvtrackd: $daemon_n new packages, $daemon_mb MiB installed (apt: $apt_says; apt's default, Recommends of the dependencies too; --no-install-recommends: $norec_n packages, $norec_mb MiB)"
heavy=$(join -v2 -t$'\t' "$work/before.txt" "$work/after-daemon.txt" | cut -f1 |
        grep -E 'java|jre|jdk|opencv|ffmpeg|libav|gdal|mesa' || true)
check daemon_size "$daemon_n new packages, $daemon_mb MiB (< 60 MiB; apt says $apt_says); --no-install-recommends: $norec_n, $norec_mb MiB" \
  awk -v mb="$daemon_mb" 'BEGIN { exit !(mb < 60) }'
check daemon_heavy "no Java, no OpenCV${heavy:+ (found: $(echo $heavy))}" test -z "$heavy"
check daemon_note "postinst: not enabled, says what to do" \
  grep -q "mvtrackd: installed, not enabled" "$work/install-daemon.log"
check daemon_state "postinst ran deb-systemd-helper update-state" \
  test -f "$root/var/lib/systemd/deb-systemd-helper-enabled/mvtrackd.service.dsh-also"
check daemon_not_enabled "the unit is not enabled" \
  test ! -e "$root/etc/systemd/system/multi-user.target.wants/mvtrackd.service"
version=$(in_root mvtrackd --version)
check daemon_version "$version" test "${version%% *}" = mvtrackd
check conffiles "conffiles $(in_root dpkg-query -W -f='${Conffiles}' mvtrackd | awk 'NF { printf "%s ", $1 }')" \
  test -f "$root/etc/mvtrack/mvtrackd.yaml"

# 2. The unit's reload command, with what the minimal system has.
echo
echo "== ExecReload of the installed unit"
unit=$root/usr/lib/systemd/system/mvtrackd.service
reload_line=$(sed -n 's/^ExecReload=//p' "$unit")
echo "ExecReload=$reload_line"
mapfile -t reload_argv < <(python3 -c 'import shlex, sys; print("\n".join(shlex.split(sys.argv[1])))' "$reload_line")
procps=$(in_root dpkg-query -W -f='${Status}' procps 2>/dev/null || true)
echo "procps in the chroot: ${procps:-not installed}"
mkdir -p "$root/tmp/reload"
cp examples/demo/calibration.yaml "$root/tmp/reload/"
printf 'format: mvtrack.daemon/1\ncameras:\n  calibration: calibration.yaml\ninput:\n  lcm_url: "memq://"\ntracker:\n  mode: poses\n  layout: coco17\n' \
  >"$root/tmp/reload/mvtrackd.yaml"
chroot "$root" /usr/bin/env -i PATH=/usr/bin:/bin /usr/bin/mvtrackd --config /tmp/reload/mvtrackd.yaml \
  >"$root/tmp/reload/daemon.log" 2>&1 &
daemon_pid=$!
for _ in $(seq 100); do grep -q "input memq://" "$root/tmp/reload/daemon.log" && break; sleep 0.1; done
# As systemd runs it: MAINPID in the environment, no PATH (a built-in kill or nothing).
in_root_reload() { chroot "$root" /usr/bin/env -i MAINPID=$daemon_pid "${reload_argv[@]}"; }
reload_rc=0
in_root_reload || reload_rc=$?
for _ in $(seq 100); do grep -q "configuration reloaded" "$root/tmp/reload/daemon.log" && break; sleep 0.1; done
kill -TERM $daemon_pid 2>/dev/null || true
daemon_rc=0
wait $daemon_pid || daemon_rc=$?
sed 's/^/  mvtrackd: /' "$root/tmp/reload/daemon.log" | grep -E 'input memq|reload|summary|error' || true
reload_ok() { [ "$reload_rc" -eq 0 ] && grep -q "configuration reloaded" "$root/tmp/reload/daemon.log"; }
check reload "$reload_line (exit $reload_rc) reloaded mvtrackd; procps ${procps:-not installed}" \
  reload_ok
check reload_stop "mvtrackd exit $daemon_rc after SIGTERM" test "$daemon_rc" -eq 0

# 3. The man page.
echo
echo "== man mvtrackd"
MANWIDTH=80 man --warnings -l "$root/usr/share/man/man8/mvtrackd.8.gz" >"$work/man-l.txt" 2>"$work/man-l.err" || true
man_l_ok() { [ ! -s "$work/man-l.err" ] && grep -q '^SYNOPSIS' "$work/man-l.txt"; }
check man_l "man -l of the installed mvtrackd.8.gz (host's man-db): no warnings, $(wc -l <"$work/man-l.txt") lines" \
  man_l_ok
snapshot "$work/before-man.txt"
in_root apt-get install -y --no-install-recommends man-db >"$work/install-man.log" 2>&1 ||
  { cat "$work/install-man.log" >&2; die "apt-get install man-db failed"; }
in_root sh -c 'MANWIDTH=80 man mvtrackd' >"$work/man.txt" 2>&1 || true
sed -n '1,8p' "$work/man.txt"
man_ok() { grep -q '^NAME' "$work/man.txt" && grep -q '^SYNOPSIS' "$work/man.txt" && grep -q '^FILES' "$work/man.txt"; }
check man "man mvtrackd (man-db in the chroot): NAME, SYNOPSIS, FILES" man_ok
# Later measurements start after man-db.
snapshot "$work/after-man.txt"

# 4. mvtrack-tools and the demo.
echo
echo "== apt-get install ./$deb_tools"
read -r tools_norec_n tools_norec_mb < <(norec_estimate "$deb_tools")
in_root apt-get install -y "/tmp/debs/$deb_tools" >"$work/install-tools.log" 2>&1 ||
  { tail -30 "$work/install-tools.log" >&2; die "apt-get install ./$deb_tools failed"; }
snapshot "$work/after-tools.txt"
read -r tools_n tools_mb < <(new_packages "$work/after-man.txt" "$work/after-tools.txt")
echo "mvtrack-tools: $tools_n new packages, $tools_mb MiB installed (--no-install-recommends: $tools_norec_n, $tools_norec_mb MiB)"
tools_java=$(join -v2 -t$'\t' "$work/after-man.txt" "$work/after-tools.txt" | cut -f1 | grep -E 'java|jre|jdk' || true)
check tools_deps "$tools_n new packages, $tools_mb MiB (--no-install-recommends: $tools_norec_n, $tools_norec_mb MiB), no Java${tools_java:+ (found: $(echo $tools_java))}" \
  test -z "$tools_java"
mkdir -p "$root/tmp/demo"
cp examples/demo/calibration.yaml examples/demo/detections.lcmlog examples/demo/gt.jsonl \
   "$root/tmp/demo/"
# The demo configuration names its site file relative to the source tree: beside it here.
cp docs/examples/sites/demo.yaml "$root/tmp/demo/site.yaml"
sed 's|^  site: .*|  site: site.yaml|' examples/demo/mvtrackd.yaml >"$root/tmp/demo/mvtrackd.yaml"
echo "-- mvtrackd --config /tmp/demo/mvtrackd.yaml --input-log /tmp/demo/detections.lcmlog"
demo_rc=0
in_root mvtrackd --config /tmp/demo/mvtrackd.yaml --input-log /tmp/demo/detections.lcmlog \
  --tracks-jsonl /tmp/demo/tracks.jsonl >"$work/demo-daemon.log" 2>&1 || demo_rc=$?
grep -E 'summary|error' "$work/demo-daemon.log" | sed 's/^/  /' || true
echo "-- mvtrack eval --gt /tmp/demo/gt.jsonl --pred /tmp/demo/tracks.jsonl"
in_root mvtrack eval --gt /tmp/demo/gt.jsonl --pred /tmp/demo/tracks.jsonl >"$work/demo-eval.txt" 2>&1 ||
  demo_rc=$?
grep -v 'Protocol:' "$work/demo-eval.txt"
# The row under "MOTA% MOTP[m] IDF1% ...".
read -r mota _ idf1 _ < <(awk 'seen { print; exit } /MOTA%/ { seen = 1 }' "$work/demo-eval.txt") || true
frames=$(wc -l <"$root/tmp/demo/tracks.jsonl" 2>/dev/null || echo 0)
same=""
if [ -z "$debs_dir" ] && [ -x "$build/daemon/mvtrackd" ]; then
  # The build tree's daemon on the same log: the packaged one must write the same bytes.
  "$build/daemon/mvtrackd" --config examples/demo/mvtrackd.yaml \
    --input-log examples/demo/detections.lcmlog --tracks-jsonl "$work/host-tracks.jsonl" \
    >"$work/host-daemon.log" 2>&1 || true
  if cmp -s "$work/host-tracks.jsonl" "$root/tmp/demo/tracks.jsonl"; then
    same=", tracks byte-identical to $build's"
  else
    same=", tracks DIFFER from $build's"
  fi
fi
demo_ok() { [ "$demo_rc" -eq 0 ] && [ "$frames" -gt 0 ] && [ -n "$mota" ] && [ "${same#*DIFFER}" = "$same" ]; }
check demo "mvtrackd + mvtrack eval on examples/demo: $frames frames, MOTA ${mota:-?} %, IDF1 ${idf1:-?} %$same" \
  demo_ok
in_root mvtrack demo >"$work/mvtrack-demo.txt" 2>&1 && demo2_rc=0 || demo2_rc=$?
awk 'seen { print "  mvtrack demo: " $0; exit } /MOTA%/ { print "  mvtrack demo: " $0; seen = 1 }' "$work/mvtrack-demo.txt"
check mvtrack_demo "mvtrack demo: exit $demo2_rc" test "$demo2_rc" -eq 0
# The operator's documents and the demo recording are installed, and the recording is the
# post-install smoke test (issue 42).
docs_ok() {
  [ -s "$root/usr/share/doc/mvtrack-tools/OPERATING.md" ] &&
    [ -s "$root/usr/share/doc/mvtrack-tools/FORMATS.md" ] &&
    [ -s "$root/usr/share/mvtrack/demo/detections.lcmlog" ] &&
    [ -s "$root/usr/share/mvtrack/demo/gt.jsonl" ]
}
check installed_docs "OPERATING.md, FORMATS.md and the demo recording installed" docs_ok
in_root mvtrack demo --installed >"$work/smoke.txt" 2>&1 && smoke_rc=0 || smoke_rc=$?
smoke_line=$(grep "smoke test" "$work/smoke.txt" | head -1)
check smoke_test "mvtrack demo --installed: exit $smoke_rc (${smoke_line#mvtrack demo: })" \
  test "$smoke_rc" -eq 0
view_rc=0
rm -f "$root/tmp/demo/frame.png"
in_root mvtrack view /tmp/demo/tracks.jsonl --calibration /tmp/demo/calibration.yaml \
  --detections /tmp/demo/detections.lcmlog --frame 150 --png /tmp/demo/frame.png \
  >"$work/view.log" 2>&1 || view_rc=$?
view_ok() { [ "$view_rc" -eq 0 ] && [ -s "$root/tmp/demo/frame.png" ]; }
check view "mvtrack view --png (mvtrack-pictures, OpenCV): exit $view_rc, $(stat -c %s "$root/tmp/demo/frame.png" 2>/dev/null || echo 0) bytes" \
  view_ok
in_root sh -c 'MANWIDTH=80 man mvtrack-replay' >"$work/man-replay.txt" 2>&1 || true
in_root sh -c 'MANWIDTH=80 man mvtrack' >"$work/man-mvtrack.txt" 2>&1 || true
man_tools_ok() { grep -q '^SYNOPSIS' "$work/man-replay.txt" && grep -q '^SEE ALSO' "$work/man-mvtrack.txt"; }
check man_tools "man mvtrack, man mvtrack-replay (chroot)" man_tools_ok

# 5. The Python types.
echo
echo "== apt-get install ./$deb_python"
in_root apt-get install -y "/tmp/debs/$deb_python" >"$work/install-python.log" 2>&1 ||
  { tail -30 "$work/install-python.log" >&2; die "apt-get install ./$deb_python failed"; }
py_out=$(in_root python3 -c '
import importlib.metadata, mvtrack
m = mvtrack.tracks3d_t(); m.utime = 7; m.frame = 3
d = mvtrack.tracks3d_t.decode(m.encode())
print("mvtrack-lcmtypes", importlib.metadata.version("mvtrack-lcmtypes"), "frame", d.frame)' 2>&1) || true
echo "$py_out"
in_root apt-get purge -y python3-mvtrack-lcmtypes >"$work/purge-python.log" 2>&1 && py_rc=0 || py_rc=$?
py_left=$( (find "$root/usr/lib/python3/dist-packages" "$root/usr/share/mvtrack/python" \
             "$root/usr/share/doc/python3-mvtrack-lcmtypes" -name '*mvtrack*' 2>/dev/null || true) |
          head -3 | sed "s|^$root||")
python_ok() { [[ $py_out == *"frame 3"* ]] && [ "$py_rc" -eq 0 ] && [ -z "$py_left" ]; }
check python "import mvtrack with Debian's python3 ($py_out); purge exit $py_rc, ${py_left:+left: $py_left}${py_left:-nothing left}" \
  python_ok

# mvtrack-spy (optional: Java).
if [ "$with_spy" = 1 ]; then
  echo
  deb_spy=$(deb_of mvtrack-spy)
  echo "== apt-get install ./$deb_spy"
  in_root apt-get install -y "/tmp/debs/$deb_spy" >"$work/install-spy.log" 2>&1 ||
    { tail -30 "$work/install-spy.log" >&2; die "apt-get install ./$deb_spy failed"; }
  cp_out=$(in_root mvtrack-spy --print-classpath 2>&1) || true
  spy_ok() { [[ $cp_out == */usr/share/java/mvtrack_lcmtypes.jar* ]] && in_root java -version >/dev/null 2>&1; }
  check spy "mvtrack-spy --print-classpath: $cp_out" spy_ok
fi

# 6. Remove, then purge mvtrackd.
echo
echo "== apt-get remove mvtrackd; apt-get purge mvtrackd"
in_root apt-get remove -y mvtrackd >"$work/remove.log" 2>&1 && rm_rc=0 || rm_rc=$?
grep -iE 'error|warning|removing' "$work/remove.log" | sed 's/^/  /' || true
status=$(in_root dpkg-query -W -f='${db:Status-Abbrev}' mvtrackd 2>/dev/null || true)
remove_ok() {
  [ "$rm_rc" -eq 0 ] && [ "$status" = "rc " ] && [ -f "$root/etc/mvtrack/mvtrackd.yaml" ] &&
    [ ! -e "$unit" ] && ! grep -qiE '^(E:|W:|dpkg: (error|warning))|script returned error' "$work/remove.log"
}
check remove "remove exit $rm_rc, status '${status% }', conffiles kept, unit gone, no script error" \
  remove_ok
in_root apt-get purge -y mvtrackd >"$work/purge.log" 2>&1 && purge_rc=0 || purge_rc=$?
grep -iE 'error|warning|purging' "$work/purge.log" | sed 's/^/  /' || true
left=""
for f in /etc/mvtrack /var/lib/systemd/deb-systemd-helper-enabled/mvtrackd.service.dsh-also \
         /var/lib/mvtrackd /usr/share/doc/mvtrackd; do
  [ -e "$root$f" ] && left+=" $f"
done
status=$(in_root dpkg-query -W -f='${db:Status-Abbrev}' mvtrackd 2>/dev/null || echo "not known")
purge_ok() {
  [ "$purge_rc" -eq 0 ] && [ -z "$left" ] &&
    ! grep -qiE '^(E:|W:|dpkg: (error|warning))|script returned error' "$work/purge.log"
}
check purge "purge exit $purge_rc, ${status:+status '$status', }${left:+left:$left}${left:-nothing left (/etc/mvtrack, state, deb-systemd-helper)}" \
  purge_ok

# 7. Optional: upgrade the old single package to the split ones.
if [ -n "$upgrade_from" ]; then
  echo
  echo "== apt-get install ./$(basename "$upgrade_from"), then the split packages over it"
  in_root apt-get purge -y mvtrack-tools >"$work/purge-tools.log" 2>&1 || true
  mkdir -p "$root/tmp/debs/old"
  cp "$upgrade_from" "$root/tmp/debs/old/"
  old=/tmp/debs/old/$(basename "$upgrade_from")
  in_root apt-get install -y "$old" >"$work/install-old.log" 2>&1 ||
    { tail -30 "$work/install-old.log" >&2; die "apt-get install $old failed"; }
  old_version=$(in_root dpkg-query -W -f='${Version}' mvtrack)
  mapfile -t split < <(cd "$work/debs" && ls *.deb | sed 's|^|/tmp/debs/|')
  up_rc=0
  in_root apt-get install -y "${split[@]}" >"$work/upgrade.log" 2>&1 || up_rc=$?
  grep -iE 'error|trying to overwrite|Unpacking mvtrack|Setting up mvtrack' "$work/upgrade.log" | sed 's/^/  /' || true
  owner=$(in_root dpkg -S /usr/bin/mvtrackd 2>/dev/null | cut -d: -f1)
  new_version=$(in_root dpkg-query -W -f='${Version}' mvtrack)
  upgrade_ok() { [ "$up_rc" -eq 0 ] && [ "$owner" = mvtrackd ] && ! grep -q 'trying to overwrite' "$work/upgrade.log"; }
  check upgrade "mvtrack $old_version -> $new_version + split packages: exit $up_rc, /usr/bin/mvtrackd now in '$owner'" \
    upgrade_ok
fi

# Summary.
echo
echo "== summary (Debian 12 bookworm, debootstrap --variant=minbase, $(chroot "$root" dpkg-query -W | wc -l) packages at the end)"
printf '%-20s %s\n' "check" "result"
for name in daemon_size daemon_heavy daemon_note daemon_state daemon_not_enabled daemon_version \
            conffiles reload reload_stop man_l man tools_deps demo mvtrack_demo installed_docs \
            smoke_test view man_tools \
            python spy remove purge upgrade; do
  [ -n "${result[$name]:-}" ] && printf '%-20s %s\n' "$name" "${result[$name]}"
done
if [ "$failed" -ne 0 ]; then
  echo "deb_chroot_test: FAILED"
  exit 1
fi
echo "deb_chroot_test: all checks passed"
