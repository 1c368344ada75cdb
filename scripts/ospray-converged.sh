#!/usr/bin/env bash
# Renders one of OSPRay 3.1's suite tests with OSPRay 3.1's runtime and with sciray at N
# times the test's pixel samples, and compares the converged images by the suite's metric:
# it tells a difference that is Monte Carlo noise (the converged images agree) from one
# that is not. With --unbiased it also renders the test with OSPRay's path tracer finding
# lights by BSDF sampling alone (lightSamples 0), an estimator that next-event estimation
# must agree with: where OSPRay's own two disagree, one of them is biased.
#   scripts/ospray-converged.sh TEST [SCALE] [--unbiased]
# e.g. scripts/ospray-converged.sh 'Light/AmbientLight.parameter/0' 64
# Extra environment for both runtimes (see ospray-converged/more_samples.c), e.g.
# OSPRAY_FLOAT_OVERRIDE=intensity:500=0 to switch off a light of intensity 500.
# BUILD_DIR (default build), OUT_DIR (default BUILD_DIR/ospray-converged) and SHARED_DIR
# (default ../shared beside the checkout) can be set. Not part of CI.
set -euo pipefail
cd "$(dirname "$0")/.."

test=${1:?usage: ospray-converged.sh TEST [SCALE] [--unbiased]}
scale=${2:-16}
unbiased=${3:-}
build_dir=${BUILD_DIR:-build}
shared=${SHARED_DIR:-../shared}
suite=$(cd "$shared/conformance/ospray-3.1" && pwd)
ospray_lib=$(cd "$shared/peers/ospray-3.1/lib" && pwd)
out=${OUT_DIR:-$build_dir/ospray-converged}

cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j "${JOBS:-$(nproc)}" --target sciray_ospray >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$(ls "$build_dir"/c_api/libsciray_ospray.so.*.*.* | head -1)" "$work/libospray.so.3"
gcc -O2 -shared -fPIC scripts/ospray-converged/more_samples.c -Ic_api/include -o "$work/more_samples.so" -ldl

rm -rf "$out"
mkdir -p "$out"
out=$(cd "$out" && pwd)
render() {  # render NAME LIBDIR [ENV...]: the test's image into OUT/NAME
  local name=$1 libdir=$2
  shift 2
  mkdir -p "$out/$name"
  (cd "$out/$name" && env OSPRAY_SAMPLES_SCALE="$scale" LD_PRELOAD="$work/more_samples.so" \
    LD_LIBRARY_PATH="$libdir:$suite/lib" "$@" "$suite/bin/ospTestSuite" --gtest_filter="$test" --dump-img \
    --baseline-dir="$out/$name" --imgsize-x=256 --imgsize-y=192 >"$out/$name.log" 2>&1) || true
  ls "$out/$name"/*.png >/dev/null 2>&1 || { echo "no image from $name (see $out/$name.log)" >&2; exit 1; }
}
image() { ls "$out/$1"/*.png | head -1; }
compare() { printf '%-26s' "$1 / $2:"; /usr/bin/python3 scripts/ospray-converged/compare.py "$(image "$1")" "$(image "$2")"; }

render ospray "$ospray_lib"
render sciray "$work"
echo "$test at $scale x its pixel samples"
compare ospray sciray
if [[ $unbiased == --unbiased ]]; then
  render ospray-bsdf "$ospray_lib" OSPRAY_LIGHT_SAMPLES=0
  compare ospray-bsdf sciray
  compare ospray ospray-bsdf
fi
echo "images in $out"
