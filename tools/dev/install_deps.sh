#!/usr/bin/env bash
# Installs the Debian 12 packages mvtrack needs, and nothing else. Idempotent: when everything is
# present it only runs dpkg-query (well under a second). Needs root (or sudo) to install.
# Usage: tools/dev/install_deps.sh [--check]   (--check: only report what is missing, exit 1 if any)
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build ccache pkg-config git
  # algorithm and runtime libraries
  libeigen3-dev libopencv-core-dev libopencv-calib3d-dev
  # tests: the reference the skeleton fit's solver is checked against (tests/body)
  libceres-dev
  # mvtrack view and calib check pictures (PNG, MP4) and OpenCV FileStorage calibrations
  libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-videoio-dev
  libyaml-cpp-dev libspdlog-dev libsystemd-dev
  # mvtrack web: HTTP server and JSON
  libcivetweb-dev nlohmann-json3-dev
  # LCM: C/C++ library, lcm-gen and the logger, Java bindings; lcm.pc needs glib
  liblcm-dev liblcm-bin liblcm-java libglib2.0-dev
  # Java types jar and lcm-spy (jchart2d draws its plots)
  default-jdk-headless libjchart2d-java
  # format check (CTest format/clang_format) and the tidy preset, pinned to Debian 12's LLVM 14
  clang-format-14 clang-tidy-14
  # tests (chromium: mvtrack web's page in a real browser, headless)
  catch2 python3 chromium curl python3-websocket
  # Python examples: a virtualenv with PyPI's lcm (tests/python)
  python3-venv
  # Debian packages: cpack -G DEB runs dpkg-shlibdeps, help2man writes the man pages
  # (tools/cmake/packaging.cmake); tests/package renders them with man
  dpkg-dev help2man man-db
  # lcm-spy GUI smoke test and screenshots (virtual X server)
  xvfb xauth
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
if [ "${1:-}" = "--check" ]; then
  echo "install_deps: missing: ${missing[*]}"
  exit 1
fi

echo "install_deps: installing ${missing[*]}"
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
