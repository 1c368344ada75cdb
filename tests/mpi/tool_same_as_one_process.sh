#!/usr/bin/env bash
# `sciray render ... --mpi` on 3 ranks writes the same image as on one process.
#   usage: tool_same_as_one_process.sh OUTDIR SCIRAY [RENDER ARGUMENTS...]
set -euo pipefail
out=$1 tool=$2
shift 2
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # CI runs as root
timeout 120 "$tool" render "$@" -o "$out/one_process.pfm"
timeout 120 mpirun --oversubscribe -n 3 "$tool" render "$@" -o "$out/three_ranks.pfm" --mpi
cmp "$out/one_process.pfm" "$out/three_ranks.pfm"
echo "three ranks: same as one process"
