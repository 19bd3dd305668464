# A fresh Debian 12 in a chroot, for the on-demand checks that need one
# (tools/dev/deb_chroot_test.sh, tools/dev/fresh_machine_test.sh). Sourced, not run. The caller sets
#   name   its name for messages;   keep   1 keeps the work directory at exit
# then calls chroot_start, which makes the work directory ($work) and installs the exit trap
# that undoes every mount, and chroot_debootstrap to make $root.

die() { echo "$name: error: $*" >&2; exit 1; }

chroot_start() {
  [ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, chroot, mount)"
  command -v debootstrap >/dev/null || die "debootstrap not found: apt-get install debootstrap"
  work=$(mktemp -d "${TMPDIR:-/var/tmp}/mvtrack-chroot.XXXXXX")
  root=$work/root
  mounted=()
  trap chroot_cleanup EXIT
  trap 'exit 130' INT
  trap 'exit 143' TERM
}

chroot_cleanup() {
  local rc=$?
  local i
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do
    umount "${mounted[$i]}" 2>/dev/null || umount -l "${mounted[$i]}" 2>/dev/null ||
      echo "$name: could not unmount ${mounted[$i]}" >&2
  done
  if [ "$keep" = 1 ]; then
    echo "$name: kept $work"
  else
    # Only once nothing is mounted below it.
    if ! grep -qF " $work/" /proc/mounts; then rm -rf "$work"; fi
  fi
  exit $rc
}

# chroot_debootstrap MIRROR TARBALL: bookworm, variant minbase (Essential and Priority: required
# packages plus apt), into $root, with proc, sys, dev and dev/pts mounted and the host's DNS.
# TARBALL (optional) is made by the first run (debootstrap --make-tarball) and unpacked by later
# ones.
chroot_debootstrap() {
  local mirror=$1 tarball=$2 start m
  echo
  echo "== debootstrap --variant=minbase bookworm ($mirror)"
  start=$(date +%s)
  if [ -n "$tarball" ]; then
    if [ ! -f "$tarball" ]; then
      debootstrap --variant=minbase --make-tarball="$tarball" bookworm "$work/tarball-tmp" "$mirror" \
        >"$work/debootstrap.log" 2>&1 || { tail -20 "$work/debootstrap.log" >&2; die "debootstrap --make-tarball failed"; }
    fi
    debootstrap --variant=minbase --unpack-tarball="$tarball" bookworm "$root" "$mirror" \
      >"$work/debootstrap.log" 2>&1 || { tail -20 "$work/debootstrap.log" >&2; die "debootstrap failed"; }
  else
    debootstrap --variant=minbase bookworm "$root" "$mirror" >"$work/debootstrap.log" 2>&1 ||
      { tail -20 "$work/debootstrap.log" >&2; die "debootstrap failed"; }
  fi
  echo "debootstrap: $(($(date +%s) - start)) s, $(chroot "$root" dpkg-query -W | wc -l) packages"
  for m in proc sys dev dev/pts; do
    mkdir -p "$root/$m"
    case $m in
      proc) mount -t proc proc "$root/proc" ;;
      sys) mount -t sysfs sysfs "$root/sys" ;;
      *) mount --bind "/$m" "$root/$m" ;;
    esac
    mounted+=("$root/$m")
  done
  cp /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
}

in_root() { chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root \
              LC_ALL=C.UTF-8 DEBIAN_FRONTEND=noninteractive "$@"; }
# snapshot FILE: the installed packages and their Installed-Size (kB), sorted.
snapshot() { in_root dpkg-query -W -f='${binary:Package}\t${Installed-Size}\n' | sort >"$1"; }
# new_packages BEFORE AFTER: "count installed-MiB" of the packages in AFTER and not in BEFORE.
new_packages() {
  join -v2 -t$'\t' "$1" "$2" | awk -F'\t' '{ n++; kb += $2 } END { printf "%d %.1f\n", n, kb / 1024 }'
}
