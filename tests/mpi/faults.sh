#!/usr/bin/env bash
# The cases of mpi_faults.c, each under mpirun, bounded in time; checks what they print.
#   usage: faults.sh OUTDIR MPI_FAULTS
set -uo pipefail
out=$1 program=$2
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # CI runs as root
failed=0
expect() {  # NAME PATTERN: the case's output must match
  if grep -q -- "$2" "$out/$1.log"; then echo "$1: ok ($2)"; else cat "$out/$1.log"; echo "FAILED: $1 lacks '$2'" >&2; failed=1; fi
}

timeout 60 mpirun --oversubscribe -n 1 "$program" funneled >"$out/funneled.log" 2>&1
expect funneled "error: ospDeviceCommit: MPI runs at thread level MPI_THREAD_FUNNELED.*MPI_THREAD_SERIALIZED"

timeout 60 mpirun --oversubscribe -n 2 "$program" serialized >"$out/serialized.log" 2>&1
expect serialized "^ready: 1$"

start=$(date +%s)
timeout 60 mpirun --oversubscribe -x SCIRAY_MPI_TIMEOUT=2 -n 2 "$program" skip >"$out/skip.log" 2>&1
expect skip "error: ospRenderFrame: mpi: .* did not complete within 2.0* s"
elapsed=$(($(date +%s) - start))
if ((elapsed > 30)); then echo "FAILED: skip took ${elapsed} s, expected about the 2 s timeout" >&2; failed=1; fi

timeout 60 mpirun --oversubscribe -n 2 "$program" overlap >"$out/overlap.log" 2>&1
expect overlap "error: ospRenderFrame: mpiDistributed: the regions of ranks 0 and 1 overlap"

timeout 60 mpirun --oversubscribe -n 2 "$program" multiple >"$out/multiple.log" 2>&1
expect multiple "^frame done after [0-9]* MPI calls of the application$"
if grep -q "^error" "$out/multiple.log"; then cat "$out/multiple.log"; echo "FAILED: multiple reported an error" >&2; failed=1; fi
exit $failed
