#!/usr/bin/env bash
# One-step set-up for a fresh Debian 12 machine: installs the Debian packages sciray
# needs (if missing), configures and builds, then does what was asked:
#   scripts/dev.sh render   renders the built-in scene to sciray.png
#   scripts/dev.sh test     runs the whole test suite
#   scripts/dev.sh packages [MORE...]  installs the packages (and MORE) only
# BUILD_DIR (default build) and JOBS (default: all cores) can be set in the environment.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config libembree-dev libxsimd-dev libtbb-dev libstb-dev catch2
          libbenchmark-dev nlohmann-json3-dev libcli11-dev libglm-dev zlib1g-dev libpugixml-dev libtinyobjloader-dev python3 python3-dev pybind11-dev python3-pytest
          python3-matplotlib python3-numpy python3-vtk9 xvfb xauth libopenmpi-dev openmpi-bin)
# `scripts/dev.sh packages [MORE...]`: these and MORE (scripts/fuzz.sh adds clang).
[ "${1:-}" = packages ] && packages+=("${@:2}")
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
fi

[ "${1:-}" = packages ] && exit 0  # only the packages (scripts/sanitize.sh, scripts/fuzz.sh)

build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}
werror=OFF
[ "${CI:-}" = true ] && werror=ON
# Debian's interpreter, whose numpy, pytest and VTK the packages above installed (not another
# python3 that may come first on PATH).
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSCIRAY_WERROR=$werror -DPython3_EXECUTABLE=/usr/bin/python3

case "${1:-}" in
  render)
    # Only the tool and the shim it links: the first picture does not wait for the tests
    # and benchmarks.
    cmake --build "$build_dir" -j "$jobs" --target sciray_tool
    "$build_dir/examples/sciray" render -o sciray.png
    ;;
  test)
    cmake --build "$build_dir" -j "$jobs"
    ctest --test-dir "$build_dir" --output-on-failure -j "$jobs"
    ;;
  *)
    echo "usage: scripts/dev.sh render|test" >&2
    exit 2
    ;;
esac
