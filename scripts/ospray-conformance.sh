#!/usr/bin/env bash
# Runs OSPRay 3.1's own test suite against sciray: builds the C API shim (Release), then
# shared/conformance/ospray-3.1/run.sh with the shim standing in for libospray.so.3, each
# test's image compared with OSPRay 3.1's own render by the suite's metric.
#   scripts/ospray-conformance.sh [TESTS.tsv | --unshared]
# --unshared runs the suite's tests that tests.tsv does not list (97 of its 356), against
# references rendered first by OSPRay 3.1's own runtime (SHARED_DIR/peers/ospray-3.1) with
# the suite's --dump-img, into OUT_DIR/references.
# BUILD_DIR (default build), OUT_DIR (default BUILD_DIR/ospray-conformance) and
# SHARED_DIR (default ../shared beside the checkout) can be set in the environment.
# About 12 minutes on 2 cores for the 259 shared tests. Not part of CI: the suite's
# binaries are a yardstick kept outside the project.
# Prints the suite's lines, a breakdown of the failures (OUT_DIR/image-noise.tsv tells
# noise from different images), and last the suite's own "N passed, M failed".
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=${BUILD_DIR:-build}
shared=${SHARED_DIR:-../shared}
suite=$shared/conformance/ospray-3.1
[ -x "$suite/run.sh" ] || [ -f "$suite/run.sh" ] || { echo "no OSPRay suite at $suite (set SHARED_DIR)" >&2; exit 2; }
out=${OUT_DIR:-$build_dir/ospray-conformance}

cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j "${JOBS:-$(nproc)}" --target sciray_ospray
# A copy of the library, so that a rebuild during the run cannot change it under the suite.
snapshot=$(mktemp -d)
trap 'rm -rf "$snapshot"' EXIT
cp "$(ls "$build_dir"/c_api/libsciray_ospray.so.*.*.* | head -1)" "$snapshot/libsciray_ospray.so"

rm -rf "$out"
tests=${1:-$suite/tests.tsv}
references=()
if [[ $tests == --unshared ]]; then
  ospray_lib=$(cd "$shared/peers/ospray-3.1/lib" && pwd)
  suite_lib=$(cd "$suite/lib" && pwd)
  run_ospray() { LD_LIBRARY_PATH=$ospray_lib:$suite_lib "$suite/bin/ospTestSuite" "$@"; }
  mkdir -p "$out/references"
  tests=$out/unshared.tsv
  run_ospray --gtest_list_tests 2>/dev/null | awk '/^[^ ]/ {suite = $1} /^  / {print suite $1}' |
    grep -vxF -f <(cut -f1 "$suite/tests.tsv") | awk '{print $1 "\t-\t-"}' >"$tests"
  echo "rendering $(wc -l <"$tests") references with OSPRay 3.1's runtime" >&2
  while IFS=$'\t' read -r test _; do
    run_ospray --gtest_filter="$test" --dump-img --baseline-dir="$out/references" \
      --imgsize-x=256 --imgsize-y=192 >/dev/null 2>&1 || echo "OSPRay itself fails $test" >&2
  done <"$tests"
  references=("$out/references")
fi
summary=$(bash "$suite/run.sh" "$snapshot" "$out" "$tests" "${references[@]}" | tee /dev/stderr | tail -1)

# Failures by cause: the first OSPRay error (numbers elided) or an image difference. Tests
# of the non-grid volume types belong to the volumes issue and are counted apart.
results=$out/results.tsv
non_grid=$(awk -F'\t' '$1 != "OK" && $3 ~ /unknown volume type .(unstructured|vdb|amr|particle)/' "$results" | wc -l)
echo "failures by cause:"
awk -F'\t' '$1 != "OK" {print ($1 == "FAIL" ? "image differs" : $3)}' "$results" | sed -E 's/[0-9]+/N/g' |
  cut -c1-120 | sort | uniq -c | sort -rn
echo "of the failures, $non_grid are non-grid volume tests (unstructured, vdb, amr, particle)"
# Image failures that are Monte Carlo noise (the images agree in 16x16-block means) or a
# different image (see the script for the criterion); Debian's python3, where dev.sh
# installs numpy and matplotlib.
echo "image failures, noise or a different image:"
/usr/bin/python3 scripts/ospray-image-noise.py "$out" | tee "$out/image-noise.tsv" | tail -1
echo "$summary"
