#!/usr/bin/env bash
# A README command as a new user runs it on a fresh Debian 12: debootstraps bookworm (variant
# minbase, tools/dev/chroot_lib.sh), clones the repository into /root/mvtrack at a commit (no
# build tree, no ccache), runs the command there as root and reports
# its wall time, the packages it installed (count and MiB) and whether any of them is a JDK or
# Java runtime, a browser, an X server or a linter. Not run by CI: it downloads the packages
# from the Debian mirror. Needs root, debootstrap and about 3 GB (demo) or 12 GB (test) in
# TMPDIR.
#
# Usage: tools/dev/fresh_machine_test.sh [options]
#   --command C     demo: README command 1, tools/dev/demo.sh (default; checks that it scored);
#                   test: README command 2, tools/dev/test.sh with CI=true, the datasets of
#                   ../shared bound read-only at /root/shared
#   --rev REV       the commit to run (default HEAD); an older one measures the time before a change
#   --mirror URL    Debian mirror (default http://deb.debian.org/debian)
#   --tarball FILE  reuse the debootstrap download (made on the first run, unpacked on later ones)
#   --host-ccache   share this machine's ccache (~/.cache/ccache) with the chroot: a rerun to see
#                   what fails builds in minutes, but its time is not a fresh machine's
#   --keep          keep the chroot directory (printed at the end)
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
rev=HEAD
command=demo
mirror=http://deb.debian.org/debian
tarball=""
keep=0
host_ccache=0
while [ $# -gt 0 ]; do
  case "$1" in
    --command) command=$2; shift ;;
    --rev) rev=$2; shift ;;
    --mirror) mirror=$2; shift ;;
    --tarball) tarball=$(readlink -f "$2"); shift ;;
    --host-ccache) host_ccache=1 ;;
    --keep) keep=1 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "fresh_machine_test: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
name=fresh_machine_test
case $command in demo) script=tools/dev/demo.sh ;; test) script=tools/dev/test.sh ;;
  *) echo "fresh_machine_test: --command is demo or test, not '$command'" >&2; exit 2 ;; esac
# shellcheck source=chroot_lib.sh
. "$repo/tools/dev/chroot_lib.sh"
commit=$(git -C "$repo" rev-parse --verify "$rev^{commit}" 2>/dev/null) || die "no commit '$rev' in $repo"
chroot_start
chroot_debootstrap "$mirror" "$tarball"

# A machine on this network trusts the CAs this one adds locally (an HTTPS proxy's, for PyPI):
# ca-certificates, when install_deps.sh installs it, takes them in as it takes in the host's.
if compgen -G "/usr/local/share/ca-certificates/*.crt" >/dev/null; then
  mkdir -p "$root/usr/local/share/ca-certificates"
  cp /usr/local/share/ca-certificates/*.crt "$root/usr/local/share/ca-certificates/"
fi
git clone -q --no-hardlinks "$repo" "$root/root/mvtrack"
git -C "$root/root/mvtrack" checkout -q "$commit"
if [ "$host_ccache" = 1 ]; then
  mkdir -p "$HOME/.cache/ccache" "$root/root/.cache/ccache"
  mount --bind "$HOME/.cache/ccache" "$root/root/.cache/ccache"
  mounted+=("$root/root/.cache/ccache")
fi
ci_env=""
if [ "$command" = test ]; then
  shared=$(readlink -f "$repo/../shared")
  [ -d "$shared/data" ] || die "no datasets in $repo/../shared (the tests need them with CI set)"
  mkdir -p "$root/root/shared"
  mount --bind "$shared" "$root/root/shared"
  mounted+=("$root/root/shared")
  mount -o remount,bind,ro "$root/root/shared"
  ci_env="CI=true"
fi
snapshot "$work/before.txt"
echo
echo "== $script of $(git -C "$repo" log -1 --format='%h %s' "$commit" | cut -c1-90)"
start=$(date +%s.%N)
rc=0
in_root $ci_env sh -c "cd /root/mvtrack && $script" >"$work/run.log" 2>&1 || rc=$?
end=$(date +%s.%N)
snapshot "$work/after.txt"
read -r n mb < <(new_packages "$work/before.txt" "$work/after.txt")
seconds=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.0f", b - a }')
heavy=$(join -v2 -t$'\t' "$work/before.txt" "$work/after.txt" | cut -f1 |
        grep -E 'openjdk|jdk|jre|chromium|firefox|^xserver|^xvfb|clang-tidy|clang-format' || true)
tail -4 "$work/run.log"
echo
echo "fresh_machine_test: $(git -C "$repo" rev-parse --short "$commit"): exit $rc, $seconds s" \
     "($((seconds / 60)) min $((seconds % 60)) s), $n packages installed ($mb MiB)"
echo "fresh_machine_test: JDK, browser, X server or linter among them: ${heavy:-none}" | tr '\n' ' '
echo
[ "$rc" -eq 0 ] || { tail -30 "$work/run.log" >&2; die "$script failed (exit $rc)"; }
[ "$command" != demo ] || grep -q "MOTA" "$work/run.log" || die "the demo printed no scores"
