#!/usr/bin/env bash
# Installs the Debian 12 packages one kind of use of mvtrack needs, and nothing else. Idempotent:
# when everything is present it only runs dpkg-query (well under a second). Needs root (or sudo)
# to install.
#
# Usage: tools/dev/install_deps.sh [--check | --list] [PROFILE]
#   PROFILE   run | build | pictures | package | test (default: test, everything). Each profile
#             includes the ones before it:
#     run       the shared libraries mvtrackd and mvtrack run with (the runtime Depends of the
#               Debian packages mvtrackd and mvtrack-tools; tests/package checks that they match)
#     build     + what builds them and runs the demo: README command 1 (tools/dev/demo.sh)
#     pictures  + OpenCV's imgproc, imgcodecs and videoio: mvtrack-pictures (mvtrack view, calib,
#               bench); with ffmpeg and GDAL below them, about as many packages again as `build`
#     package   + the Java types jar and mvtrack-spy, man pages, cpack -G DEB (the `package` preset)
#     test      + the test suites' own needs: README command 2 (tools/dev/test.sh, .ci/run)
#   --check   only report what is missing from PROFILE (exit 1 if anything is)
#   --list    print PROFILE's packages, one per line, and exit
set -euo pipefail

profiles=(run build pictures package test)
# The one list: profile, then the packages it adds (and why).
table=(
  # The C/C++ runtime and the libraries the two programs link (dpkg-shlibdeps' names).
  "run       libc6 libgcc-s1 libstdc++6"
  "run       liblcm1 libyaml-cpp0.7 libspdlog1.10 libfmt9 libsystemd0"   # mvtrackd
  "run       libcivetweb1"                         # mvtrack web
  # Toolchain, headers, lcm-gen (lcm.pc needs glib), and python3 (demo.sh prints the tracks).
  "build     build-essential cmake ninja-build ccache pkg-config python3"
  "build     libeigen3-dev libopencv-core-dev libyaml-cpp-dev libspdlog-dev libsystemd-dev"
  "build     libcivetweb-dev nlohmann-json3-dev liblcm-dev liblcm-bin libglib2.0-dev"
  # mvtrack-pictures draws pictures and videos.
  "pictures  libopencv-core406 libopencv-imgproc406 libopencv-imgcodecs406 libopencv-videoio406"
  "pictures  libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-videoio-dev"
  # The Java types jar and lcm-spy (jchart2d draws its plots); cpack -G DEB runs
  # dpkg-shlibdeps and `file` (CPackDeb finds the ELF files with it), help2man writes the man
  # pages (tools/cmake/packaging.cmake).
  "package   default-jdk-headless liblcm-java libjchart2d-java dpkg-dev file help2man"
  # Tests: Catch2; OpenCV calib3d and Ceres Solver as references (geometry, the skeleton fit's
  # solver); the format check and the tidy preset (Debian 12's LLVM 14); mvtrack web's page in
  # a real browser, headless; the Python examples in a virtualenv with PyPI's lcm (over HTTPS:
  # ca-certificates); man renders the packages' pages; the lcm-spy smoke test under a virtual X
  # server (a Java runtime with AWT: default-jre, what mvtrack-spy depends on); git lists the
  # sources;
  # ip (iproute2) brings up the loopback of the live tests' private network namespaces (without
  # it they skip: a minbase Debian has none).
  "test      catch2 libopencv-calib3d-dev libceres-dev clang-format-14 clang-tidy-14"
  "test      chromium curl python3-websocket python3-prometheus-client python3-venv ca-certificates man-db xvfb xauth"
  "test      default-jre git iproute2"
)

die() { echo "install_deps: $*" >&2; exit 2; }
mode=install
profile=test
while [ $# -gt 0 ]; do
  case "$1" in
    --check) mode=check ;;
    --list) mode=list ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) die "unknown option '$1' (see --help)" ;;
    *) profile=$1 ;;
  esac
  shift
done

# The profiles up to and including $profile, then their packages.
included=()
for p in "${profiles[@]}"; do
  included+=("$p")
  [ "$p" = "$profile" ] && break
done
[ "${included[-1]}" = "$profile" ] ||
  die "unknown profile '$profile' (one of: ${profiles[*]})"
packages=()
for row in "${table[@]}"; do
  read -r -a words <<<"$row"
  for p in "${included[@]}"; do
    if [ "${words[0]}" = "$p" ]; then packages+=("${words[@]:1}"); fi
  done
done

if [ "$mode" = list ]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages of profile '$profile' present"
  exit 0
fi
if [ "$mode" = check ]; then
  echo "install_deps: missing from profile '$profile': ${missing[*]}"
  exit 1
fi

echo "install_deps: installing (profile '$profile') ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then sudo="sudo"; else
    echo "install_deps: not root and no sudo; install these packages: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install_deps: done"
