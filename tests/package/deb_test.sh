# Builds the .deb with cpack and checks it: control fields, Depends covering every shared library
# of the packaged programs, contents (daemon, CLI, unit, example config, types jar), conffiles,
# the unit's paths, and `--version` of both programs run from an extracted scratch root.
# Usage: deb_test.sh CPACK BUILD_DIR WORK_DIR VERSION INSTALL_PREFIX SOURCE_DIR
set -euo pipefail
if [ $# -ne 6 ]; then
  echo "usage: $0 CPACK BUILD_DIR WORK_DIR VERSION INSTALL_PREFIX SOURCE_DIR" >&2
  exit 2
fi
CPACK=$1 BUILD=$2 WORK=$3 VERSION=$4 PREFIX=$5 SRC=$6
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"

for tool in dpkg-deb dpkg-shlibdeps dpkg; do
  command -v "$tool" >/dev/null || fail "$tool not found (Debian packages dpkg, dpkg-dev)"
done
rm -rf "$WORK"
mkdir -p "$WORK"

# 1. Build the package.
start=$(date +%s.%N)
if ! (cd "$BUILD" && "$CPACK" -G DEB -B "$WORK/out" --config "$BUILD/CPackConfig.cmake") \
    >"$WORK/cpack.log" 2>&1; then
  cat "$WORK/cpack.log" >&2
  fail "cpack -G DEB failed (is the whole build up to date? cpack installs every target)"
fi
end=$(date +%s.%N)
echo "cpack: $(python3 -c "print(f'{$end - $start:.1f}')") s"
arch=$(dpkg --print-architecture)
deb="$WORK/out/mvtrack_${VERSION}_${arch}.deb"
[ -f "$deb" ] || { ls -l "$WORK/out" >&2; fail "no $deb"; }
echo "package: $deb ($(stat -c %s "$deb") bytes)"

# 2. Control fields.
dpkg-deb -I "$deb" >"$WORK/info.txt"
dpkg-deb -f "$deb" >"$WORK/control.txt"
expect_grep "^Package: mvtrack$" "$WORK/control.txt"
expect_grep "^Version: ${VERSION//./\\.}$" "$WORK/control.txt"
expect_grep "^Architecture: $arch$" "$WORK/control.txt"
expect_grep "^Maintainer: .+" "$WORK/control.txt"
expect_grep "^Description: .+" "$WORK/control.txt"
expect_grep "^Recommends: .*liblcm-java" "$WORK/control.txt"
depends=$(dpkg-deb -f "$deb" Depends)
[ -n "$depends" ] || fail "the package declares no Depends"
echo "Depends: $depends"
# Package names of the Depends field (alternatives and version constraints dropped).
dep_names=$(echo "$depends" | tr ',|' '\n\n' | sed -E 's/\(.*\)//; s/:any//; s/^ +//; s/ +$//' |
            grep -v '^$' | sort -u)

# 3. Contents.
dpkg-deb -c "$deb" | awk '{print $NF}' | sed 's|^\./|/|' >"$WORK/contents.txt"
p=${PREFIX%/}
sysconf=$([ "$p" = /usr ] && echo /etc || echo "$p/etc")
for f in "$p/bin/mvtrack" "$p/bin/mvtrackd" "$p/bin/mvtrack-spy" \
         "$p/share/java/mvtrack_lcmtypes.jar" "$p/lib/systemd/system/mvtrackd.service" \
         "$p/share/mvtrack/python/mvtrack_lcmtypes-$VERSION-py3-none-any.whl" \
         "$sysconf/mvtrack/mvtrackd.yaml"; do
  grep -qxF "$f" "$WORK/contents.txt" || { cat "$WORK/contents.txt" >&2; fail "$f is not in the package"; }
done
echo "contents: $(grep -cv '/$' "$WORK/contents.txt") files"

# 4. Extract into a scratch root and run the programs from there.
root="$WORK/root"
dpkg-deb -x "$deb" "$root"
out=$("$root$p/bin/mvtrack" --version)
[ "$out" = "mvtrack $VERSION" ] || fail "mvtrack --version printed '$out', expected 'mvtrack $VERSION'"
echo "extracted mvtrack --version: $out"
out=$("$root$p/bin/mvtrackd" --version)
echo "$out" | grep -qF "$VERSION" || fail "mvtrackd --version printed '$out', expected $VERSION in it"
echo "extracted mvtrackd --version: $out"
# The launcher finds the packaged jar next to it (../share/java).
cp_line=$(MVTRACK_TYPES_JAR= "$root$p/bin/mvtrack-spy" --print-classpath 2>&1) ||
  fail "mvtrack-spy --print-classpath failed: $cp_line"
echo "$cp_line" | grep -qF "$root$p/share/java/mvtrack_lcmtypes.jar" ||
  fail "mvtrack-spy uses '$cp_line', not the packaged jar"
# The jar holds every type's class.
python3 - "$root$p/share/java/mvtrack_lcmtypes.jar" "$SRC/lcmtypes" <<'PY' || fail "types jar"
import os, sys, zipfile
names = set(zipfile.ZipFile(sys.argv[1]).namelist())
types = sorted(f[:-4] for f in os.listdir(sys.argv[2]) if f.endswith(".lcm"))
missing = [t for t in types if f"mvtrack/{t}.class" not in names]
if missing or not types:
    sys.exit(f"jar lacks {missing}")
print(f"types jar: {len(types)} types")
PY

# 5. Depends: the package owning every shared library the ELF files need is in Depends.
elfs=$(find "$root" -type f -perm -u+x -exec sh -c 'head -c4 "$1" | grep -q "ELF" && echo "$1"' _ {} \;)
[ -n "$elfs" ] || fail "no ELF file in the package"
for elf in $elfs; do
  ldd "$elf" >"$WORK/ldd.txt" 2>&1 || { cat "$WORK/ldd.txt" >&2; fail "ldd $elf failed"; }
  if grep -q "not found" "$WORK/ldd.txt"; then
    cat "$WORK/ldd.txt" >&2
    fail "$elf needs a library that is not installed"
  fi
  for lib in $(objdump -p "$elf" | awk '/NEEDED/ {print $2}'); do
    path=$(awk -v l="$lib" '$1 == l {print $3}' "$WORK/ldd.txt")
    [ -n "$path" ] || fail "$elf: $lib not resolved by ldd"
    owner=$(dpkg -S "$(readlink -f "$path")" 2>/dev/null | head -1 | cut -d: -f1) ||
      owner=$(dpkg -S "$path" 2>/dev/null | head -1 | cut -d: -f1) || true
    [ -n "$owner" ] || fail "$elf: no Debian package owns $path ($lib)"
    # The owner, or a virtual package it provides (libspdlog1.10 provides libspdlog1.10-fmt9).
    names=$(printf '%s\n%s\n' "$owner" "$(dpkg-query -W -f='${Provides}' "$owner" 2>/dev/null |
            tr ',' '\n' | sed -E 's/\(.*\)//; s/^ +//; s/ +$//')")
    echo "$names" | grep -v '^$' | grep -qxF -f - <(echo "$dep_names") ||
      fail "$elf needs $lib from package $owner, which Depends ($depends) does not list"
  done
done
echo "Depends covers the shared libraries of: $(echo "$elfs" | sed "s|$root||" | tr '\n' ' ')"

# 6. conffiles: exactly the files under /etc.
dpkg-deb -e "$deb" "$WORK/control"
grep -E "^/etc/" "$WORK/contents.txt" | grep -v '/$' | sort >"$WORK/etc_files.txt" || true
sort "$WORK/control/conffiles" 2>/dev/null >"$WORK/conffiles.txt" || : >"$WORK/conffiles.txt"
cmp -s "$WORK/etc_files.txt" "$WORK/conffiles.txt" ||
  { diff "$WORK/etc_files.txt" "$WORK/conffiles.txt" >&2; fail "conffiles differ from the files under /etc"; }
echo "conffiles: $(wc -l <"$WORK/conffiles.txt")"

# 7. The unit starts the packaged daemon with a packaged configuration.
unit="$root$p/lib/systemd/system/mvtrackd.service"
exec_line=$(grep -E '^ExecStart=' "$unit") || fail "no ExecStart in the unit"
bin=$(echo "${exec_line#ExecStart=}" | awk '{print $1}')
[ "$bin" = "$p/bin/mvtrackd" ] || fail "the unit runs '$bin', the package installs $p/bin/mvtrackd"
for path in $(echo "$exec_line" | grep -oE "$sysconf/mvtrack/[^ ]+" || true); do
  grep -qxF "$path" "$WORK/contents.txt" || fail "the unit names $path, which is not in the package"
done
echo "package: ok"
