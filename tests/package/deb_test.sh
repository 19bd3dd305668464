# Builds the Debian packages with cpack (one per component, tools/cmake/packaging.cmake) and checks
# every one of them: the set of packages, control fields (version, architecture, Depends from
# dpkg-shlibdeps covering every shared library of its ELF files, Breaks/Replaces of the old single
# package), the exact file list (nothing missing, nothing unexpected), which package may depend
# on Java and OpenCV, conffiles, the maintainer scripts (present, executable, `sh -n`, and run
# with a recording deb-systemd-helper), the DEP-5 copyright file, the man pages (gzipped,
# rendered without warnings), the unit, and --version of the programs run from an extracted
# scratch root.
# Usage: deb_test.sh CPACK BUILD_DIR WORK_DIR VERSION DEB_VERSION INSTALL_PREFIX SYSCONFDIR
#                    UNIT_PATH SOURCE_DIR
set -euo pipefail
if [ $# -ne 9 ]; then
  echo "usage: $0 CPACK BUILD_DIR WORK_DIR VERSION DEB_VERSION INSTALL_PREFIX SYSCONFDIR UNIT_PATH SOURCE_DIR" >&2
  exit 2
fi
CPACK=$1 BUILD=$2 WORK=$3 VERSION=$4 DEB_VERSION=$5 PREFIX=$6 SYSCONF=$7 UNIT_PATH=$8 SRC=$9
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"

for tool in dpkg-deb dpkg-shlibdeps dpkg gzip; do
  command -v "$tool" >/dev/null || fail "$tool not found (Debian packages dpkg, dpkg-dev, gzip)"
done
rm -rf "$WORK"
mkdir -p "$WORK"
p=${PREFIX%/}
arch=$(dpkg --print-architecture)
types=$(cd "$SRC/lcmtypes" && ls *.lcm | sed 's/\.lcm$//')
[ -n "$types" ] || fail "no .lcm files in $SRC/lcmtypes"

# 0. Every install rule belongs to a package (an install() without COMPONENT would be left out
#    of every package without a word).
unspecified=$(grep -rl --include=cmake_install.cmake '"Unspecified"' "$BUILD" || true)
[ -z "$unspecified" ] ||
  fail "install rules without COMPONENT (packaged nowhere) in: $(echo "$unspecified" | sed "s|$BUILD/||" | tr '\n' ' ')"

# 1. Build the packages.
start=$(date +%s.%N)
if ! (cd "$BUILD" && "$CPACK" -G DEB -B "$WORK/out" --config "$BUILD/CPackConfig.cmake") \
    >"$WORK/cpack.log" 2>&1; then
  cat "$WORK/cpack.log" >&2
  fail "cpack -G DEB failed (is the whole build up to date? cpack installs every target)"
fi
end=$(date +%s.%N)
echo "cpack: $(python3 -c "print(f'{$end - $start:.1f}')") s"
[ -f "$BUILD/cpack/packages.txt" ] || fail "no $BUILD/cpack/packages.txt (written by packaging.cmake)"
mapfile -t packages <"$BUILD/cpack/packages.txt"
for must in mvtrackd mvtrack-tools mvtrack mvtrack-lcmtypes-dev; do
  printf '%s\n' "${packages[@]}" | grep -qxF "$must" || fail "this build makes no package $must"
done
has() { printf '%s\n' "${packages[@]}" | grep -qxF "$1"; }
# The .debs cpack wrote are exactly the packages of the list.
ls "$WORK/out"/*.deb | xargs -n1 basename | sed 's/_.*//' | sort >"$WORK/written.txt"
printf '%s\n' "${packages[@]}" | sort >"$WORK/expected_packages.txt"
cmp -s "$WORK/written.txt" "$WORK/expected_packages.txt" ||
  { diff "$WORK/expected_packages.txt" "$WORK/written.txt" >&2 || true; fail "cpack wrote other packages than $BUILD/cpack/packages.txt"; }

deb_arch() {  # the Architecture a package must have
  case "$1" in mvtrackd|mvtrack-tools) echo "$arch" ;; *) echo all ;; esac
}
deb_file() { echo "$WORK/out/${1}_${DEB_VERSION}_$(deb_arch "$1").deb"; }

# The exact file list of each package (regular files and symbolic links; directories aside).
expected_files() {
  local doc=$p/share/doc/$1
  case "$1" in
    mvtrackd)
      printf '%s\n' "$p/bin/mvtrackd" "$UNIT_PATH" "$SYSCONF/mvtrack/mvtrackd.yaml" \
        "$SYSCONF/mvtrack/calibration.example.yaml" "$doc/DAEMON.md" "$doc/copyright" \
        "$p/share/man/man8/mvtrackd.8.gz" "$p/bin/mvtrack-stitcher" \
        "$(dirname "$UNIT_PATH")/mvtrack-stitcher.service" "$doc/SCALING.md" \
        "$p/share/man/man8/mvtrack-stitcher.8.gz" ;;
    mvtrack-tools)
      printf '%s\n' "$p/bin/mvtrack" "$p/bin/mvtrack-pictures" "$doc/copyright" \
        "$p/share/man/man1/mvtrack.1.gz" "$p/share/man/man1/mvtrack-pictures.1.gz" \
        "$doc/OPERATING.md" "$doc/FORMATS.md"
      for f in README.md calibration.yaml detections.lcmlog gt.jsonl; do
        echo "$p/share/mvtrack/demo/$f"
      done
      # One page per command of `mvtrack --help` (but `version`), from the built program.
      "$BUILD/tools/mvtrack" --help | awk '/^commands:/ { l = 1; next } l && /^[ \t]*$/ { exit }
        l && /^  [a-z]/ && $1 != "version" { print "'"$p"'/share/man/man1/mvtrack-" $1 ".1.gz" }' ;;
    mvtrack-spy)
      printf '%s\n' "$p/bin/mvtrack-spy" "$p/share/java/mvtrack_lcmtypes.jar" "$doc/copyright" ;;
    python3-mvtrack-lcmtypes)
      local site=$p/lib/python3/dist-packages
      printf '%s\n' "$site/mvtrack/__init__.py" "$doc/copyright" "$doc/PYTHON.md" \
        "$p/share/mvtrack/python/mvtrack_lcmtypes-$VERSION-py3-none-any.whl"
      for f in mvtrack_msgs print_site print_tracks publish_detections read_log; do
        echo "$doc/examples/$f.py"
      done
      for f in METADATA WHEEL top_level.txt; do echo "$site/mvtrack_lcmtypes-$VERSION.dist-info/$f"; done
      for t in $types; do echo "$site/mvtrack/$t.py"; done ;;
    mvtrack-lcmtypes-dev)
      echo "$doc/copyright"
      for t in $types; do echo "$p/include/mvtrack/$t.hpp"; echo "$p/share/mvtrack/lcmtypes/$t.lcm"; done ;;
    mvtrack)
      echo "$doc/copyright" ;;
    *) fail "no expected file list for package $1" ;;
  esac
}

# field PACKAGE FIELD: one control field of the built package.
field() { dpkg-deb -f "$(deb_file "$1")" "$2"; }
# names FIELD-VALUE: the package names of a relationship field, one per line.
names() { echo "$1" | tr ',|' '\n\n' | sed -E 's/\(.*\)//; s/:any//; s/^ +//; s/ +$//' | grep -v '^$' | sort -u; }

for pkg in "${packages[@]}"; do
  deb=$(deb_file "$pkg")
  [ -f "$deb" ] || { ls -l "$WORK/out" >&2; fail "no $deb"; }
  d=$WORK/$pkg
  mkdir -p "$d"

  # 2. Control fields.
  dpkg-deb -f "$deb" >"$d/control.txt"
  expect_grep "^Package: $pkg$" "$d/control.txt"
  expect_grep "^Version: ${DEB_VERSION//./\\.}$" "$d/control.txt"
  expect_grep "^Architecture: $(deb_arch "$pkg")$" "$d/control.txt"
  expect_grep "^Maintainer: .+" "$d/control.txt"
  expect_grep "^Description: .+" "$d/control.txt"
  expect_grep "^Section: .+" "$d/control.txt"
  if [ "$pkg" != mvtrack ]; then
    # The single package `mvtrack` of earlier builds (0.2.0) held these files.
    expect_eq "$(field "$pkg" Breaks)" "mvtrack (<< $DEB_VERSION~)" "$pkg Breaks"
    expect_eq "$(field "$pkg" Replaces)" "mvtrack (<< $DEB_VERSION~)" "$pkg Replaces"
  fi
  depends=$(field "$pkg" Depends)
  recommends=$(field "$pkg" Recommends)

  # 3. The file list: exactly the expected one.
  dpkg-deb -c "$deb" >"$d/listing.txt"
  awk '$1 !~ /^d/ { f = $6; sub(/^\./, "", f); print f }' "$d/listing.txt" | sort >"$d/files.txt"
  expected_files "$pkg" | sort >"$d/expected.txt"
  if ! cmp -s "$d/expected.txt" "$d/files.txt"; then
    echo "--- $pkg: expected (-) and packaged (+) files:" >&2
    { diff "$d/expected.txt" "$d/files.txt" || true; } | grep '^[<>]' | sed 's/^</-/; s/^>/+/' >&2
    fail "$pkg: the file list differs from the expected one"
  fi
  # No file outside the prefix and the configuration directory.
  if grep -vE "^($p|$SYSCONF)/" "$d/files.txt"; then fail "$pkg installs outside $p and $SYSCONF"; fi
  echo "$pkg: $(wc -l <"$d/files.txt") files, as expected; Installed-Size $(field "$pkg" Installed-Size) kB"

  # 4. Extract into a scratch root (one for all packages, as installed together).
  dpkg-deb -x "$deb" "$WORK/root"
  dpkg-deb -e "$deb" "$d/control"

  # 5. copyright: DEP-5, in every package; states the truth (no license chosen).
  c=$WORK/root$p/share/doc/$pkg/copyright
  [ "$(head -1 "$c")" = "Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/" ] ||
    fail "$pkg: $c is not machine-readable (DEP-5 Format: line)"
  expect_grep "^Upstream-Name: mvtrack$" "$c"
  expect_grep "^Files: \*$" "$c"
  expect_grep "^Copyright: .*mvtrack authors" "$c"
  expect_grep "^License: all-rights-reserved$" "$c"
  expect_grep "No license has been chosen" "$c"
  # Every field line is "Name: value", a continuation (" ...") or a blank paragraph separator.
  if grep -nvE '^([A-Za-z-]+: .*| .+|)$' "$c"; then fail "$pkg: $c has lines that are not DEP-5"; fi

  # 6. Depends: the package owning every shared library of the package's ELF files is listed.
  elfs=$(awk '$1 ~ /^-..x/ { f = $6; sub(/^\./, "", f); print f }' "$d/listing.txt" |
         while read -r f; do head -c4 "$WORK/root$f" | grep -q ELF && echo "$WORK/root$f"; done || true)
  dep_names=$(names "$depends")
  for elf in $elfs; do
    ldd "$elf" >"$d/ldd.txt" 2>&1 || { cat "$d/ldd.txt" >&2; fail "ldd $elf failed"; }
    if grep -q "not found" "$d/ldd.txt"; then cat "$d/ldd.txt" >&2; fail "$elf needs a library that is not installed"; fi
    for lib in $(objdump -p "$elf" | awk '/NEEDED/ {print $2}'); do
      path=$(awk -v l="$lib" '$1 == l {print $3}' "$d/ldd.txt")
      [ -n "$path" ] || fail "$elf: $lib not resolved by ldd"
      owner=$(dpkg -S "$(readlink -f "$path")" 2>/dev/null | head -1 | cut -d: -f1) ||
        owner=$(dpkg -S "$path" 2>/dev/null | head -1 | cut -d: -f1) || true
      [ -n "$owner" ] || fail "$elf: no Debian package owns $path ($lib)"
      echo "$owner" >>"$WORK/owners-$(basename "$elf").txt"
      # The owner, or a virtual package it provides (libspdlog1.10 provides libspdlog1.10-fmt9).
      provided=$(printf '%s\n%s\n' "$owner" "$(dpkg-query -W -f='${Provides}' "$owner" 2>/dev/null |
                 tr ',' '\n' | sed -E 's/\(.*\)//; s/^ +//; s/ +$//')")
      echo "$provided" | grep -v '^$' | grep -qxF -f - <(echo "$dep_names") ||
        fail "$pkg: $elf needs $lib from package $owner, which Depends ($depends) does not list"
    done
  done
  [ -z "$elfs" ] || echo "$pkg: Depends covers the shared libraries of $(echo "$elfs" | sed "s|$WORK/root||" | tr '\n' ' ')"
  if [ "$(deb_arch "$pkg")" = all ] && [ -n "$elfs" ]; then fail "$pkg is Architecture: all but has ELF files"; fi

  # 7. Which package may pull in what: Java only by mvtrack-spy, OpenCV only by mvtrack-tools.
  rel_names=$(names "$depends, $recommends")
  java=$(echo "$rel_names" | grep -E 'java|jre|jdk' || true)
  opencv=$(echo "$rel_names" | grep -E 'opencv' || true)
  case "$pkg" in
    mvtrack-spy)
      echo "$depends" | grep -qE '(^|, )default-jre( |,|$)' || fail "mvtrack-spy: no Java runtime in Depends ($depends)"
      for j in liblcm-java libjchart2d-java; do
        echo "$dep_names" | grep -qxF "$j" || fail "mvtrack-spy: $j not in Depends ($depends)"
      done ;;
    mvtrack)
      [ -z "$java" ] || fail "mvtrack: Java in Depends/Recommends ($java)" ;;
    *)
      [ -z "$java" ] || fail "$pkg: Java in Depends/Recommends ($java): only mvtrack-spy may need it" ;;
  esac
  case "$pkg" in
    mvtrack-tools) [ -n "$opencv" ] || fail "mvtrack-tools: no OpenCV in Depends ($depends)" ;;
    mvtrack) ;;
    *) [ -z "$opencv" ] || fail "$pkg: OpenCV in Depends/Recommends ($opencv)" ;;
  esac

  # 8. conffiles: exactly the package's files under the configuration directory.
  (grep -E "^$SYSCONF/" "$d/files.txt" || true) | sort >"$d/etc_files.txt"
  if [ -f "$d/control/conffiles" ]; then sort "$d/control/conffiles" >"$d/conffiles.txt"; else : >"$d/conffiles.txt"; fi
  cmp -s "$d/etc_files.txt" "$d/conffiles.txt" ||
    { diff "$d/etc_files.txt" "$d/conffiles.txt" >&2 || true; fail "$pkg: conffiles differ from its files under $SYSCONF"; }

  # 9. Maintainer scripts: exactly these, executable, valid sh.
  case "$pkg" in
    mvtrackd) want_scripts="postinst postrm prerm" ;;
    python3-mvtrack-lcmtypes) want_scripts="postinst prerm" ;;
    *) want_scripts="" ;;
  esac
  have_scripts=$(cd "$d/control" && ls | { grep -E '^(preinst|postinst|prerm|postrm|config|triggers)$' || true; } |
                 sort | tr '\n' ' ' | sed 's/ $//')
  expect_eq "$have_scripts" "$want_scripts" "$pkg maintainer scripts"
  for s in $want_scripts; do
    [ -x "$d/control/$s" ] || fail "$pkg: $s is not executable"
    [ "$(head -1 "$d/control/$s")" = "#!/bin/sh" ] || fail "$pkg: $s does not start with #!/bin/sh"
    sh -n "$d/control/$s" || fail "$pkg: $s is not valid sh"
    expect_grep "^set -e$" "$d/control/$s"
  done
  echo "$pkg: Depends: ${depends:-(none)}${recommends:+; Recommends: $recommends}; conffiles $(wc -l <"$d/conffiles.txt"); scripts: ${want_scripts:-none}"
done

# 9b. install_deps.sh's `run` profile is exactly what the two programs run with (the owners of
#     the shared libraries of mvtrackd and mvtrack), and what mvtrack-pictures needs beyond it
#     is the runtime part of the `pictures` profile: `install_deps.sh run` (or `build`, the
#     demo's) installs all that the packaged programs load, and nothing they do not.
profile() { bash "$SRC/tools/dev/install_deps.sh" --list "$1" | sort -u; }
for f in mvtrackd mvtrack mvtrack-pictures; do
  [ -s "$WORK/owners-$f.txt" ] || fail "no shared libraries recorded for bin/$f"
done
sort -u "$WORK/owners-mvtrackd.txt" "$WORK/owners-mvtrack.txt" >"$WORK/run_owners.txt"
profile run >"$WORK/run_profile.txt"
cmp -s "$WORK/run_owners.txt" "$WORK/run_profile.txt" ||
  { diff "$WORK/run_profile.txt" "$WORK/run_owners.txt" >&2 || true
    fail "install_deps.sh's run profile (<) differs from the packages owning mvtrackd's and mvtrack's libraries (>)"; }
sort -u "$WORK/owners-mvtrack-pictures.txt" | comm -23 - "$WORK/run_profile.txt" >"$WORK/pictures_owners.txt"
comm -23 <(profile pictures) <(profile build) | grep -v -- '-dev$' >"$WORK/pictures_profile.txt" || true
cmp -s "$WORK/pictures_owners.txt" "$WORK/pictures_profile.txt" ||
  { diff "$WORK/pictures_profile.txt" "$WORK/pictures_owners.txt" >&2 || true
    fail "install_deps.sh's pictures libraries (<) differ from what mvtrack-pictures needs beyond the run profile (>)"; }
echo "install_deps.sh: run profile = the libraries of mvtrackd and mvtrack ($(tr '\n' ' ' <"$WORK/run_profile.txt")); pictures adds $(tr '\n' ' ' <"$WORK/pictures_owners.txt")"

# 10. mvtrackd's maintainer scripts, run with a deb-systemd-helper that records its calls (no
#     systemd here: the [ -d /run/systemd/system ] branches are skipped, as in a chroot).
C=$WORK/mvtrackd/control
stub=$WORK/stub
mkdir -p "$stub/bin"
cat >"$stub/bin/deb-systemd-helper" <<'EOF'
#!/bin/sh
echo "$(basename "$0") $*" >>"$STUB_LOG"
case "$1" in
  debian-installed) [ -n "$STUB_INSTALLED" ] ;;
  --quiet) [ -n "$STUB_ENABLED" ] ;;
  *) exit 0 ;;
esac
EOF
cp "$stub/bin/deb-systemd-helper" "$stub/bin/deb-systemd-invoke"  # logs under its own name
chmod +x "$stub/bin/"*
# run_script NAME INSTALLED ENABLED ARGS...: the script's deb-systemd-* calls that change
# something, one per line (the queries debian-installed and was-enabled answer INSTALLED and
# ENABLED: non-empty = yes).
run_script() {
  local name=$1 installed=$2 enabled=$3
  shift 3
  : >"$stub/log"
  env PATH="$stub/bin:/usr/bin:/bin" STUB_LOG="$stub/log" STUB_INSTALLED="$installed" \
    STUB_ENABLED="$enabled" DPKG_ROOT="$stub/dpkgroot" sh "$C/$name" "$@" >"$stub/out" 2>&1 ||
    { cat "$stub/out" >&2; fail "mvtrackd $name $* exited non-zero"; }
  grep -vE '^deb-systemd-helper (debian-installed|--quiet was-enabled) ' "$stub/log" || true
}
unit=mvtrackd.service
# A first installation: only the state file; nothing enabled, nothing started; a note.
got=$(run_script postinst "" "" configure "")
expect_eq "$got" "deb-systemd-helper update-state $unit" "postinst configure (first installation)"
expect_grep "not enabled" "$stub/out"
# An upgrade of an installation the administrator enabled: re-enabled (new symlinks), no note.
got=$(run_script postinst yes yes configure 0.2.0-0 | tr '\n' ';')
expect_eq "$got" "deb-systemd-helper unmask $unit;deb-systemd-helper enable $unit;deb-systemd-helper update-state $unit;" \
  "postinst configure (upgrade, enabled)"
[ ! -s "$stub/out" ] || fail "postinst on upgrade printed: $(cat "$stub/out")"
# An upgrade of one left disabled: stays disabled.
got=$(run_script postinst yes "" configure 0.2.0-0 | tr '\n' ';')
expect_eq "$got" "deb-systemd-helper unmask $unit;deb-systemd-helper update-state $unit;" \
  "postinst configure (upgrade, disabled)"
got=$(run_script prerm "" "" remove)
expect_eq "$got" "" "prerm remove without systemd"
got=$(run_script postrm "" "" remove)
expect_eq "$got" "" "postrm remove"
# Purge: deb-systemd-helper purge (postrm looks for /usr/bin/deb-systemd-helper, as debhelper's
# does), and the state directory goes (systemd's DynamicUser layout, below DPKG_ROOT here).
mkdir -p "$stub/dpkgroot/var/lib/private/mvtrackd"
touch "$stub/dpkgroot/var/lib/private/mvtrackd/track_ids"
ln -sfn private/mvtrackd "$stub/dpkgroot/var/lib/mvtrackd"
got=$(run_script postrm "" "" purge)
if [ -x /usr/bin/deb-systemd-helper ]; then
  expect_eq "$got" "deb-systemd-helper purge $unit" "postrm purge"
fi
[ ! -e "$stub/dpkgroot/var/lib/private/mvtrackd" ] && [ ! -L "$stub/dpkgroot/var/lib/mvtrackd" ] ||
  fail "postrm purge left the state directory"
# The guards: every systemctl and deb-systemd-invoke call sits behind [ -d /run/systemd/system ].
for s in postinst prerm postrm; do
  awk '/\[ -d \/run\/systemd\/system \]/ { g++ } /^\tfi$|^fi$/ { if (g) g-- }
       /systemctl|deb-systemd-invoke/ && !/^[ \t]*(#|echo )/ && !g { print FILENAME ": " $0; bad = 1 }
       END { exit bad }' "$C/$s" || fail "mvtrackd $s calls systemd outside the /run/systemd/system guard"
done
echo "mvtrackd maintainer scripts: first install (not enabled), upgrade (enabled / disabled), remove, purge: ok"
if has python3-mvtrack-lcmtypes; then
  expect_grep "py3compile -p python3-mvtrack-lcmtypes" "$WORK/python3-mvtrack-lcmtypes/control/postinst"
  expect_grep "py3clean -p python3-mvtrack-lcmtypes" "$WORK/python3-mvtrack-lcmtypes/control/prerm"
fi

# 11. Programs from the extracted root.
root=$WORK/root
out=$("$root$p/bin/mvtrack" --version)
expect_eq "$out" "mvtrack $VERSION" "mvtrack --version"
echo "extracted mvtrack --version: $out"
out=$("$root$p/bin/mvtrackd" --version)
expect_eq "$out" "mvtrackd $VERSION" "mvtrackd --version"
echo "extracted mvtrackd --version: $out"
# mvtrack runs the packaged mvtrack-pictures next to it.
expect_exit 0 "$WORK/pictures.log" "$root$p/bin/mvtrack" calib --help
expect_grep "^usage: mvtrack calib" "$WORK/pictures.log"
if has mvtrack-spy; then
  cp_line=$(MVTRACK_TYPES_JAR= "$root$p/bin/mvtrack-spy" --print-classpath 2>&1) ||
    fail "mvtrack-spy --print-classpath failed: $cp_line"
  echo "$cp_line" | grep -qF "$root$p/share/java/mvtrack_lcmtypes.jar" ||
    fail "mvtrack-spy uses '$cp_line', not the packaged jar"
  python3 - "$root$p/share/java/mvtrack_lcmtypes.jar" $types <<'PY' || fail "types jar"
import sys, zipfile
names = set(zipfile.ZipFile(sys.argv[1]).namelist())
missing = [t for t in sys.argv[2:] if f"mvtrack/{t}.class" not in names]
if missing:
    sys.exit(f"jar lacks {missing}")
print(f"types jar: {len(sys.argv) - 2} types")
PY
fi
if has python3-mvtrack-lcmtypes; then
  # Debian's python3 imports the packaged module from dist-packages; the metadata is there.
  out=$(cd / && PYTHONPATH=$root$p/lib/python3/dist-packages PYTHONDONTWRITEBYTECODE=1 python3 -c '
import importlib.metadata, mvtrack, sys
m = mvtrack.tracks3d_t(); m.frame = 42
assert mvtrack.tracks3d_t.decode(m.encode()).frame == 42
assert mvtrack.__file__.startswith(sys.argv[1]), mvtrack.__file__
print("python3: import mvtrack from", sys.argv[1], "version", importlib.metadata.version("mvtrack-lcmtypes"))' \
    "$root$p/lib/python3/dist-packages") || fail "the packaged Python types do not import: $out"
  echo "$out"
  echo "$out" | grep -qF "version $VERSION" || fail "python3-mvtrack-lcmtypes metadata version is not $VERSION"
fi
if has mvtrack; then
  expect_eq "$(field mvtrack Depends)" "mvtrackd (= $DEB_VERSION), mvtrack-tools (= $DEB_VERSION)" "mvtrack Depends"
fi

# 12. Man pages: gzipped (-9n: no name, no time), render without warnings, name their program.
man_pages=$(grep -hE "^$p/share/man/man[18]/" "$WORK"/*/files.txt)
[ -n "$man_pages" ] || fail "no man pages in the packages"
for m in $man_pages; do
  f=$root$m
  if [ -L "$f" ]; then
    [ "$(readlink "$f")" = mvtrack.1.gz ] || fail "$m links to $(readlink "$f"), not mvtrack.1.gz"
    continue
  fi
  [ "$(head -c2 "$f" | od -An -tx1 | tr -d ' ')" = 1f8b ] || fail "$m is not gzipped"
  gzip -t "$f" || fail "$m: gzip -t fails"
  # gzip -n: no file name (flag bit 3) and no time stamp in the header.
  read -r _ _ _ flags m0 m1 m2 m3 < <(od -An -tx1 -N8 "$f")
  [ $((0x$flags & 8)) -eq 0 ] && [ "$m0$m1$m2$m3" = 00000000 ] ||
    fail "$m: gzipped with a name or time stamp (use gzip -9n)"
  page=$(basename "$m" .gz)
  th=$(zcat "$f" | grep -m1 '^\.TH' | tr -d '"\\')
  [ "$(echo "$th" | awk '{ print $2, $3 }')" = "$(echo "${page%.*}" | tr a-z A-Z) ${page##*.}" ] ||
    fail "$m: header '$th', expected .TH $(echo "${page%.*}" | tr a-z A-Z) ${page##*.}"
  if command -v man >/dev/null; then
    MANWIDTH=80 man --warnings -l "$f" >"$WORK/man.txt" 2>"$WORK/man.err" || fail "man -l $m failed"
    [ ! -s "$WORK/man.err" ] || { cat "$WORK/man.err" >&2; fail "man -l $m warns"; }
    for section in NAME SYNOPSIS DESCRIPTION "SEE ALSO"; do
      grep -q "^$section" "$WORK/man.txt" || fail "$m has no $section section"
    done
  fi
done
zcat "$root$p/share/man/man8/mvtrackd.8.gz" | grep -q '^\.SH FILES' || fail "mvtrackd(8) has no FILES section"
# The man pages that send the reader to OPERATING.md name where the package installs it.
for cmd in status web; do
  zcat "$root$p/share/man/man1/mvtrack-$cmd.1.gz" | sed 's/\\-/-/g' |
    grep -q "$p/share/doc/mvtrack-tools/OPERATING\.md" ||
    fail "mvtrack-$cmd(1) does not name the installed $p/share/doc/mvtrack-tools/OPERATING.md"
done
grep -qx "$p/share/doc/mvtrack-tools/OPERATING.md" "$WORK/mvtrack-tools/files.txt" ||
  fail "mvtrack-tools does not install OPERATING.md"
# The packaged demo recording passes the smoke test (the chroot test runs `--installed`).
expect_exit 0 "$WORK/smoke.txt" "$root$p/bin/mvtrack" demo --recording "$root$p/share/mvtrack/demo"
expect_grep "smoke test passed" "$WORK/smoke.txt"
echo "man pages: $(echo "$man_pages" | wc -l), gzipped$(command -v man >/dev/null && echo ", rendered by man -l without warnings")"

# 13. The unit starts the packaged daemon with a packaged configuration; reload needs only an
#     Essential package (tests/daemon/unit_reload_test.sh runs it against a daemon).
unit_file=$root$UNIT_PATH
exec_line=$(grep -E '^ExecStart=' "$unit_file") || fail "no ExecStart in the unit"
bin=$(echo "${exec_line#ExecStart=}" | awk '{print $1}')
[ "$bin" = "$p/bin/mvtrackd" ] || fail "the unit runs '$bin', the package installs $p/bin/mvtrackd"
for path in $(echo "$exec_line" | grep -oE "$SYSCONF/mvtrack/[^ ]+" || true); do
  grep -qxF "$path" "$WORK/mvtrackd/files.txt" || fail "the unit names $path, which is not in the package"
done
reload=$(sed -n 's/^ExecReload=//p' "$unit_file")
expect_eq "$reload" "/bin/sh -c 'kill -HUP \$MAINPID'" "the unit's ExecReload"
grep -qE '^Documentation=.*man:mvtrackd\(8\)' "$unit_file" || fail "the unit's Documentation= does not name mvtrackd(8)"
for doc in $(sed -n 's/^Documentation=//p' "$unit_file" | tr ' ' '\n' | sed -n 's|^file:||p'); do
  grep -qxF "$doc" "$WORK/mvtrackd/files.txt" || fail "the unit's Documentation= names $doc, which is not in the package"
done
echo "package: ok ($(echo "${packages[@]}"))"
