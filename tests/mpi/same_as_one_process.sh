#!/usr/bin/env bash
# An OSPRay program renders the same bytes on one process and under mpirun with the
# mpiOffload device: with the task queue on 3 and 2 ranks, with static tiles, and with
# the workers launched as their own program (MPMD).
#   usage: same_as_one_process.sh OUTDIR WORKER PROGRAM [ARGS...]
# PROGRAM ARGS OUTPUT must write its result to OUTPUT. Each run is bounded by `timeout`.
set -euo pipefail
out=$1 worker=$2
shift 2
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # CI runs as root
mpi=(timeout 120 mpirun --oversubscribe)
offload=(--osp:load-modules=mpi_offload --osp:device=mpiOffload)

"$@" "$out/one_process.out" >/dev/null
run() {
  local name=$1
  shift
  "$@" >"$out/$name.log" 2>&1 || { cat "$out/$name.log"; echo "FAILED: $name exited with an error" >&2; exit 1; }
  cmp "$out/one_process.out" "$out/$name.out" || { echo "FAILED: $name differs from one process" >&2; exit 1; }
  echo "$name: same as one process"
}
run three_ranks "${mpi[@]}" -n 3 "$@" "${offload[@]}" "$out/three_ranks.out"
run two_ranks "${mpi[@]}" -n 2 "$@" "${offload[@]}" "$out/two_ranks.out"
run static_tiles "${mpi[@]}" -x SCIRAY_MPI_STATIC_TILES=1 -n 3 "$@" "${offload[@]}" "$out/static_tiles.out"
run mpmd "${mpi[@]}" -n 1 "$@" "${offload[@]}" "$out/mpmd.out" : -n 2 "$worker"
