#!/usr/bin/env bash
# sciray against OSPRay 3.1 through the same OSPRay C API client (../shared/peers/osp_bench.c),
# one engine after the other for each case, REPS rounds; peak memory from GNU time.
#
#   bench/peers/side_by_side.sh [BUILD_DIR] [OUT_DIR]      (CASES="spheres_ao16 mesh_scivis" picks)
#   python3 bench/ratio.py OUT_DIR/side_by_side.jsonl
#
# OSPRay is a yardstick, never a dependency: its runtime is only read from SHARED_DIR/peers.
# The scenes come from the peers' generators (the mesh needs Debian's python3-vtk9).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=$(mkdir -p "${2:-$build/peers}" && cd "${2:-$build/peers}" && pwd)
shared=$(cd "${SHARED_DIR:-$root/../shared}" && pwd)
peers=$shared/peers
reps=${REPS:-1}
size=${SIZE:-1024}

# OSPRay's lib/ holds its version links as small text files naming their targets.
osplib=$out/ospray-lib
mkdir -p "$osplib"
for f in "$peers"/ospray-3.1/lib/*; do
  name=$(basename "$f")
  if [[ $(stat -c %s "$f") -lt 100 ]]; then ln -sfn "$(cat "$f")" "$osplib/$name"; else ln -sfn "$f" "$osplib/$name"; fi
done
scilib=$out/sciray-lib
mkdir -p "$scilib"
cp "$(ls "$build"/c_api/libsciray_ospray.so.*.*.* | head -1)" "$scilib/libsciray_ospray.so"
ln -sfn libsciray_ospray.so "$scilib/libsciray_ospray.so.0"
cc -O2 -std=c99 "$peers/osp_bench.c" -I"$root/c_api/include" -L"$scilib" -Wl,-rpath,"$scilib" -lsciray_ospray -lm \
  -o "$out/bench_sciray"
cc -O2 -std=c99 "$peers/osp_bench.c" -I"$peers/ospray-3.1/include" -L"$osplib" -Wl,-rpath,"$osplib" -lospray -lm \
  -o "$out/bench_ospray"

scenes=$out/scenes
mkdir -p "$scenes"
[[ -f $scenes/sph1m.xyzr ]] || /usr/bin/python3 "$peers/gen_spheres.py" "$scenes" sph1m 1000000 >&2
if [[ ! -f $scenes/iso-m.ply ]]; then
  /usr/bin/python3 -c 'import vtk' 2>/dev/null || { echo "the mesh scenes need python3-vtk9 (apt-get install python3-vtk9)" >&2; exit 2; }
  /usr/bin/python3 "$peers/gen_iso.py" "$scenes" iso-m 420 3 >&2
fi
embryo="$shared/data/volumes/embryo_256x256x256_uint8.raw:256:256:256:uint8"

mesh="mesh $scenes/iso-m.ply $scenes/iso-m.camera.json"
spheres="spheres $scenes/sph1m.xyzr $scenes/sph1m.camera.json"
declare -A case_args=(
  [mesh_scivis]="$mesh $size $size 10 scivis"
  [mesh_scivis_shadows]="$mesh $size $size 10 scivis shadows"
  [spheres_scivis_shadows]="$spheres $size $size 10 scivis shadows"
  [spheres_ao16]="$spheres $size $size 5 ao ao=16"
  [mesh_ao4]="$mesh $size $size 5 ao ao=4"
  [mesh_pathtracer]="$mesh $size $size 5 pathtracer"
  [spheres_pathtracer]="$spheres $size $size 5 pathtracer"
  [embryo_dvr]="volume $embryo $here/embryo_tf.json $here/embryo.camera.json $size $size 10 1"
)
cases=${CASES:-"mesh_scivis mesh_scivis_shadows spheres_scivis_shadows spheres_ao16 mesh_ao4 mesh_pathtracer spheres_pathtracer embryo_dvr"}

results=$out/side_by_side.jsonl
: >"$results"
cd "$out"
for round in $(seq "$reps"); do
  for name in $cases; do
    for engine in ospray sciray; do
      # shellcheck disable=SC2086  # the case's arguments are words
      line=$(/usr/bin/time -f 'peak_kb %M' -o "$out/time.txt" "./bench_$engine" ${case_args[$name]} 2>/dev/null | tail -1)
      peak=$(awk '/peak_kb/ {print $2}' "$out/time.txt")
      cp out.ppm "$out/${name}_$engine.ppm"
      echo "{\"case\": \"$name\", \"engine\": \"$engine\", \"round\": $round, \"peak_kb\": $peak, ${line#\{}" | tee -a "$results"
    done
  done
done
echo "wrote $results; python3 bench/ratio.py $results" >&2
