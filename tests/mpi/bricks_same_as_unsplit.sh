#!/usr/bin/env bash
# A volume cut into 2, 3 and 4 bricks over as many ranks of the mpiDistributed device
# composites to the unsplit volume's image, within MAX_RMSE (linear RGBA).
#   usage: bricks_same_as_unsplit.sh OUTDIR PROGRAM VOLUME MAX_RMSE [PROGRAM OPTIONS...]
set -euo pipefail
out=$1 program=$2 volume=$3 max_rmse=$4
shift 4
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # CI runs as root
timeout 120 "$program" "$volume" "$out/unsplit.png" --unsplit --rgba "$out/unsplit.rgba" "$@"
for ranks in 2 3 4; do
  timeout 120 mpirun --oversubscribe -n "$ranks" "$program" "$volume" "$out/bricks_$ranks.png" \
    --compare "$out/unsplit.rgba" "$max_rmse" "$@"
done
