#!/usr/bin/env bash
# The test suite under sanitizers, in a build folder of its own:
#   scripts/sanitize.sh address   AddressSanitizer + UndefinedBehaviorSanitizer (and LeakSanitizer): every test
#   scripts/sanitize.sh thread    ThreadSanitizer: the tests that run threads against each other
# BUILD_DIR (default build-asan / build-tsan) and JOBS (default: all cores) can be set. The
# Python module and the benchmarks are left out (an instrumented extension needs the
# sanitizer runtime preloaded into python3). Figures: docs/reliability.md.
set -euo pipefail
cd "$(dirname "$0")/.."
kind=${1:-}
case "$kind" in
  # float-cast-overflow: GCC leaves it out of "undefined" (a float beyond an integer's
  # range converted to it); the fuzzers found two such.
  address) sanitize=address,undefined,float-cast-overflow; default_dir=build-asan ;;
  thread) sanitize=thread; default_dir=build-tsan ;;
  *) echo "usage: scripts/sanitize.sh address|thread" >&2; exit 2 ;;
esac
build_dir=${BUILD_DIR:-$default_dir}
jobs=${JOBS:-$(nproc)}
scripts/dev.sh packages
# -O1 -g1: the per-ISA translation units compile in a fraction of the time -O2 takes under
# the sanitizers, and findings still come with file and line.
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="-O1 -g1" -DSCIRAY_SANITIZE=$sanitize -DSCIRAY_BUILD_BENCH=OFF \
      -DSCIRAY_BUILD_PYTHON=OFF -DPython3_EXECUTABLE=/usr/bin/python3
if [ "$kind" = thread ]; then
  cmake --build "$build_dir" -j "$jobs" --target sciray_tests  # the only program it runs
  # ThreadSanitizer sees only the synchronization of instrumented code. Debian's libtbb is
  # not instrumented: every wait for a task would look like a race. So oneTBB is built from
  # Debian's own source package (the version of libtbb-dev's headers) with
  # -fsanitize=thread, and the tests run with it. (Embree stays uninstrumented: tests/tsan.supp.)
  tbb_lib=$PWD/$build_dir/onetbb/lib
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  if [ ! -f "$tbb_lib/libtbb.so.12" ]; then
    if ! apt-get source --print-uris -qq onetbb >/dev/null 2>&1; then
      sources=/etc/apt/sources.list.d/sciray-deb-src.sources
      printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: bookworm bookworm-updates\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' |
        $sudo tee "$sources" >/dev/null
      $sudo apt-get update -qq
    fi
    rm -rf "$build_dir/onetbb"
    mkdir -p "$build_dir/onetbb/src"
    (cd "$build_dir/onetbb/src" && apt-get source -qq --download-only onetbb && tar xf onetbb_*.orig.tar.*)
    tbb_source=$(find "$build_dir/onetbb/src" -mindepth 1 -maxdepth 1 -type d | head -1)
    cmake -S "$tbb_source" -B "$build_dir/onetbb/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTBB_SANITIZE=thread \
          -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF -DTBBMALLOC_BUILD=OFF -DTBB_STRICT=OFF >/dev/null
    cmake --build "$build_dir/onetbb/build" -j "$jobs" --target tbb
    mkdir -p "$tbb_lib"
    cp -P "$(dirname "$(find "$build_dir/onetbb/build" -name 'libtbb.so.12' | head -1)")"/libtbb.so* "$tbb_lib/"
  fi
  export LD_LIBRARY_PATH=$tbb_lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
else
  cmake --build "$build_dir" -j "$jobs"
fi

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/tsan.supp}
start=$(date +%s)
if [ "$kind" = thread ]; then
  # The C API from several threads (frames racing commits, cancels and releases), and the
  # engine's tile-parallel frames and frame buffers (oneTBB), in one process.
  "$build_dir/tests/sciray_tests" "[threads],[render],[frame],[distributed]"
else
  ctest --test-dir "$build_dir" --output-on-failure -j "$jobs" --timeout 3600
fi
echo "sanitize.sh $kind: tests ran clean in $(( $(date +%s) - start )) s"
