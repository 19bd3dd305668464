#!/usr/bin/env bash
# Writes the man pages of the installed programs with help2man, from the programs' own --help
# and --version (run by the build: target mvtrack_man_pages, tools/cmake/packaging.cmake):
#   OUT/man8/mvtrackd.8.gz          mvtrackd --help, plus tools/packaging/mvtrackd.h2m.in (FILES,
#                                   SEE ALSO)
#   OUT/man8/mvtrack-stitcher.8.gz  mvtrack-stitcher --help (next to MVTRACKD), plus
#                                   mvtrack-stitcher.h2m.in
#   OUT/man1/mvtrack.1.gz           mvtrack --help, plus mvtrack.h2m.in (ENVIRONMENT, NOTES, SEE
#                                   ALSO naming the pages below)
#   OUT/man1/mvtrack-CMD.1.gz       mvtrack CMD --help, one page per command that `mvtrack --help`
#                                   lists (git's scheme: man mvtrack-replay)
#   OUT/man1/mvtrack-pictures.1.gz  a symbolic link to mvtrack.1.gz (the helper that mvtrack
#                                   execs for bench, view and calib has no --help of its own)
# gzip -9n, as Debian wants (dh_compress). The date is SOURCE_DATE_EPOCH's, else the source's
# last commit's, else today's. The programs' "usage:" block is rewritten into help2man's form
# ("Usage:", continuation lines joined, further forms as "  or:") so it becomes the SYNOPSIS;
# nothing else of the text is changed.
#
# Usage: make_man_pages.sh HELP2MAN OUT_DIR MVTRACK MVTRACKD H2M_DIR SOURCE_DIR
#   H2M_DIR holds mvtrackd.h2m, mvtrack-stitcher.h2m, mvtrack.h2m (configured with the install
#   paths) and
#   mvtrack-command.h2m.
set -euo pipefail
if [ $# -ne 6 ]; then
  echo "usage: $0 HELP2MAN OUT_DIR MVTRACK MVTRACKD H2M_DIR SOURCE_DIR" >&2
  exit 2
fi
HELP2MAN=$1 OUT=$2 MVTRACK=$3 MVTRACKD=$4 H2M=$5 SRC=$6

die() { echo "make_man_pages: error: $*" >&2; exit 1; }
[ -x "$HELP2MAN" ] || die "help2man not found at '$HELP2MAN' (Debian package help2man)"

if [ -z "${SOURCE_DATE_EPOCH:-}" ]; then
  SOURCE_DATE_EPOCH=$(git -C "$SRC" log -1 --format=%ct 2>/dev/null || true)
  [ -n "$SOURCE_DATE_EPOCH" ] || unset SOURCE_DATE_EPOCH
fi
[ -z "${SOURCE_DATE_EPOCH:-}" ] || export SOURCE_DATE_EPOCH
# Sanitizer builds: a leak report at exit must not fail a --help.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}

rm -rf "$OUT/man1" "$OUT/man8" "$OUT/wrap"
mkdir -p "$OUT/man1" "$OUT/man8" "$OUT/wrap"

# wrapper NAME PROGRAM [ARGS...]: OUT/wrap/NAME runs `PROGRAM ARGS... --help` with the usage
# block in help2man's form, and prints "NAME (mvtrack) VERSION" for --version.
wrapper() {
  local name=$1 program=$2
  shift 2
  local args=""
  for a in "$@"; do args+=" $(printf '%q' "$a")"; done
  cat >"$OUT/wrap/$name" <<EOF
#!/usr/bin/env bash
set -euo pipefail
if [ "\${1:-}" = --version ]; then
  v=\$($(printf '%q' "$program") --version)
  echo "$name (mvtrack) \${v##* }"
  exit 0
fi
$(printf '%q' "$program")$args "\$@" | awk '
  NR == 1 && /^usage: / { sub(/^usage: /, "Usage: "); u = \$0; prog = \$2; inusage = 1; next }
  inusage && /^[ \t]*\$/ { print u; inusage = 0; print; next }
  inusage && \$1 == prog { print u; sub(/^[ \t]+/, ""); u = "  or: " \$0; next }
  inusage { sub(/^[ \t]+/, ""); u = u " " \$0; next }
  { print }
  END { if (inusage) print u }'
EOF
  chmod +x "$OUT/wrap/$name"
}

# page NAME SECTION DESCRIPTION [help2man options...]
page() {
  local name=$1 section=$2 description=$3
  shift 3
  "$HELP2MAN" --no-info --section "$section" --name "$description" \
    "$@" --output "$OUT/man$section/$name.$section" "$OUT/wrap/$name" ||
    die "help2man failed on $name"
  [ -s "$OUT/man$section/$name.$section" ] || die "help2man wrote an empty page for $name"
  gzip -9nf "$OUT/man$section/$name.$section"
}

# The commands of `mvtrack --help` ("commands:" block: name, two or more spaces, description).
commands=$("$MVTRACK" --help | awk '
  /^commands:/ { in_list = 1; next }
  in_list && /^[ \t]*$/ { exit }
  in_list && /^  [a-z]/ { print }')
[ -n "$commands" ] || die "'$MVTRACK --help' lists no commands"

see_also=""
while read -r cmd description; do
  [ "$cmd" = version ] && continue       # `mvtrack version` = --version: no page of its own
  wrapper "mvtrack-$cmd" "$MVTRACK" "$cmd"
  page "mvtrack-$cmd" 1 "$description" --include "$H2M/mvtrack-command.h2m"
  see_also+=".BR mvtrack-$cmd (1),"$'\n'
done <<<"$commands"

wrapper mvtrack "$MVTRACK"
# mvtrack.h2m's SEE ALSO names the command pages where it says %COMMAND_PAGES%.
awk -v pages="$see_also" '$0 == "%COMMAND_PAGES%" { printf "%s", pages; next } { print }' \
  "$H2M/mvtrack.h2m" >"$OUT/wrap/mvtrack.h2m"
page mvtrack 1 "multi-view multi-person 3D tracking: replay, convert, evaluate, simulate, draw" \
  --include "$OUT/wrap/mvtrack.h2m"
ln -sf mvtrack.1.gz "$OUT/man1/mvtrack-pictures.1.gz"

wrapper mvtrackd "$MVTRACKD"
page mvtrackd 8 "multi-view multi-person 3D tracking daemon (LCM in, LCM out)" \
  --include "$H2M/mvtrackd.h2m"

# The site stitcher is built next to mvtrackd (daemon/).
wrapper mvtrack-stitcher "$(dirname "$MVTRACKD")/mvtrack-stitcher"
page mvtrack-stitcher 8 "joins the tracks of a site's zone daemons into one id space" \
  --include "$H2M/mvtrack-stitcher.h2m"

echo "make_man_pages: $(ls "$OUT/man1" "$OUT/man8" | grep -c '\.gz$') pages in $OUT"
