#!/usr/bin/env bash
# Fuzzes every file reader and the C API with libFuzzer (ASan + UBSan): builds the targets
# in fuzz/ (the C API target against the shim, built by clang with the same sanitizers in
# <FUZZ_BUILD>/shim), makes their seed corpora (from the shared data sets,
# fuzz/make_seeds.py's tiny files and fuzz/make_c_api_seeds.py's scenes of API calls),
# runs each for FUZZ_SECONDS, one after another, and prints per target the executions,
# the coverage (cov: and ft: of libFuzzer's last status line) and whether it found a crash,
# leak, undefined behaviour or hang. Not run by CI. Exits 1 when any target found something.
#   scripts/fuzz.sh                 all targets
#   scripts/fuzz.sh ply nrrd        only these (fuzz/fuzz_<name>.cpp)
# Environment: FUZZ_SECONDS (default 60) per target; FUZZ_BUILD (default build-fuzz) for
# the binaries, corpora, logs and crash reproducers (crashes/<target>/, to replay:
# <FUZZ_BUILD>/fuzz_<target> <file>); SCIRAY_DATA_DIR (default ../shared/data).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/dev.sh packages clang-14 libclang-rt-14-dev

seconds=${FUZZ_SECONDS:-60}
build=${FUZZ_BUILD:-build-fuzz}
data=${SCIRAY_DATA_DIR:-../shared/data}
if [ ! -f "$data/meshes/bunny.ply" ]; then
  echo "fuzz.sh: no shared data sets at $data (put shared/ beside the checkout or set SCIRAY_DATA_DIR)" >&2
  exit 2
fi

# Inputs longer than this are not tried: large enough for a header and a few records of
# each format, small enough that each run is quick.
declare -A max_len=([ply]=8192 [points]=8192 [obj]=4096 [pdb]=8192 [volume_raw]=2048 [nrrd]=2048
                    [vtu]=8192 [vti]=4096 [vtp]=8192 [legacy_vtk]=4096 [shading_json]=1024
                    [transfer_function]=1024 [c_api]=4096)
# Words of each format (fuzz/<name>.dict) that mutations insert whole.
declare -A dict=([vtu]=vtk_xml [vti]=vtk_xml [vtp]=vtk_xml [legacy_vtk]=legacy_vtk [nrrd]=nrrd [obj]=obj
                 [volume_raw]=volume_raw [shading_json]=shading_json [transfer_function]=transfer_function)
if (($#)); then
  targets=("$@")
else
  targets=(ply points obj pdb volume_raw nrrd vtu vti vtp legacy_vtk shading_json transfer_function c_api)
fi
for t in "${targets[@]}"; do
  [ -f "fuzz/fuzz_$t.cpp" ] || { echo "fuzz.sh: no target fuzz/fuzz_$t.cpp" >&2; exit 2; }
done

mkdir -p "$build"
rm -rf "$build/seeds"
python3 fuzz/make_seeds.py "$data" "$build/seeds"
python3 fuzz/make_c_api_seeds.py "$build/seeds/c_api"

# shellcheck disable=SC2054  # the commas are in a compiler flag
flags=(-std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
       -Iinclude -Ic_api/include -Iexamples/sciray)
libs=(-ltbb -lembree3 -lpugixml -lz -ltinyobjloader -lstb)
for t in "${targets[@]}"; do
  echo "building fuzz_$t"
  if [ "$t" = c_api ]; then
    # The shim as CMake builds it, by clang with libFuzzer's coverage instrumentation and
    # the same sanitizers (the ISA objects are localized by GNU ld, as in the regular
    # build); the target links it as an application does.
    cmake -S . -B "$build/shim" -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=None \
          -DCMAKE_CXX_FLAGS="-O1 -g -fsanitize=fuzzer-no-link" -DSCIRAY_SANITIZE=address,undefined \
          -DSCIRAY_BUILD_TESTS=OFF -DSCIRAY_BUILD_BENCH=OFF -DSCIRAY_BUILD_EXAMPLES=OFF -DSCIRAY_BUILD_PYTHON=OFF \
          -DSCIRAY_MPI=OFF -DCMAKE_LINKER=ld.bfd >"$build/shim.log"
    cmake --build "$build/shim" -j "$(nproc)" --target sciray_ospray >>"$build/shim.log"
    shim_lib=$(cd "$build/shim/c_api" && pwd)
    clang++-14 "${flags[@]}" fuzz/fuzz_c_api.cpp -o "$build/fuzz_c_api" -L"$shim_lib" -lsciray_ospray -Wl,-rpath,"$shim_lib"
  else
    clang++-14 "${flags[@]}" "fuzz/fuzz_$t.cpp" -o "$build/fuzz_$t" "${libs[@]}"
  fi
done

# UB aborts the run (-fno-sanitize-recover), with the stack that reached it. libFuzzer
# reports a single allocation over -rss_limit_mb as out-of-memory: a finding too.
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
summary=()
found=0
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t" crashes="$build/crashes/$t" log="$build/logs/$t.log"
  mkdir -p "$corpus" "$crashes" "$build/logs"
  echo "fuzzing $t for ${seconds}s (log: $log)"
  options=(-max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -max_len="${max_len[$t]:-4096}"
           -artifact_prefix="$crashes/" -print_final_stats=1)
  [ -z "${dict[$t]:-}" ] || options+=(-dict="fuzz/${dict[$t]}.dict")
  status=0
  "$build/fuzz_$t" "$corpus" "$build/seeds/$t" "${options[@]}" >"$log" 2>&1 &
  pid=$!
  wait $pid || status=$?
  # The target's scratch files (fuzz/fuzz_support.hpp), left behind when a finding ended it.
  rm -rf "/dev/shm/sciray-fuzz-$pid" "${TMPDIR:-/tmp}/sciray-fuzz-$pid"
  executions=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || true)
  [ -n "$executions" ] || executions=$(grep -o '^#[0-9]*' "$log" | tail -1 | tr -d '#' || true)
  coverage=$(grep -o 'cov: [0-9]* ft: [0-9]*' "$log" | tail -1 || true)
  artifact=$(grep -o 'Test unit written to [^ ]*' "$log" | tail -1 | sed 's/Test unit written to //' || true)
  if ((status != 0)) || [ -n "$artifact" ]; then
    found=1
    what=$(grep -m1 -oE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer): [^ ]+( [^ ]+)?|runtime error: .*' "$log" || true)
    result="FOUND (${what:-exit status $status}): ${artifact:-see the log}"
  else
    result="nothing found"
  fi
  summary+=("$(printf '%-18s %6ss %11s  %-22s %s' "$t" "$seconds" "${executions:-?}" "${coverage:-cov: ? ft: ?}" "$result")")
done

echo
echo "target             seconds  executions  coverage               result"
printf '%s\n' "${summary[@]}"
exit $found
