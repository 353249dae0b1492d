#!/bin/bash
# Decomposed-run scaling measurements (docs/parallel.md, "Scaling"; issue 27, item 6): per-rank
# peak memory, ghost bytes and messages per step and collectives, 1-8 ranks (oversubscribed),
# 0.1-3.1 M tets; then checkpoint sizes and write times on 913 k tets. Not part of CI.
# usage: bench/scaling/run.sh BRITTLE OUT_DIR   (prints one line per run; then fit.py OUT_DIR/scale.txt)
set -u
B=$(realpath "$1"); R=$(realpath -m "$2"); mkdir -p "$R"; cd "$(dirname "$0")/../.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
declare -A MESH
for m in "250e-6 2 m115k" "167e-6 3 m385k" "125e-6 4 m913k" "100e-6 5 m1776k" "83e-6 6 m3100k"; do
  set -- $m  # the RM plate at a uniform h, meshed once and read back as a VTU by every run
  [ -f "$R/$3/frames/frame_0000.vtu" ] || "$B" run scenes/rm.ini --set mesh.size=$1 --set mesh.band=0 \
    --set mesh.layers=$2 --set run.end_time=1e-8 --set output.frame_interval=1e-6 --out "$R/$3" >/dev/null 2>&1
  MESH[$3]=$R/$3/frames/frame_0000.vtu
done
run="run scenes/rm.ini --set run.threads=1 --set run.end_time=0.2e-6 --set output.vtu=false --set output.frame_interval=0"
for m in m115k m385k m913k m1776k m3100k; do
  for np in 1 2 4 8; do
    [ $m = m3100k ] && [ $np = 8 ] && continue  # 8 copies of the whole 3 M mesh
    out=$R/${m}_np$np
    mpirun --oversubscribe -np $np "$B" $run --set mesh.file=${MESH[$m]} --out "$out" > "$out.log" 2>&1
    python3 - "$out" <<'PY'
import json, sys
d = json.load(open(sys.argv[1] + '/summary.json')); dd = d.get('decomposition', {}); rs = dd.get('ranks', [])
print(sys.argv[1].split('/')[-1], d['tets'], d['steps'], round(d['wall_seconds'], 2), 'coll/step',
      round(dd.get('collectives_per_step', 0), 2), 'rss_mb', [round(r['peak_rss_mb']) for r in rs],
      'tets', [r['tets'] for r in rs], 'B/step', [round(r['ghost_bytes_per_step']) for r in rs],
      'msg/step', [round(r['messages_per_step'], 1) for r in rs])
PY
  done
  /usr/bin/time -f "%e s %M KB" -o "$R/${m}_serial.time" "$B" $run --set mesh.file=${MESH[$m]} --out "$R/${m}_serial" >/dev/null 2>&1
  echo "$m serial $(cat "$R/${m}_serial.time")"
done
for np in 1 2 4; do  # checkpoint size and write time, two sets each
  out=$R/ckpt_np$np
  mpirun --oversubscribe -np $np "$B" $run --set mesh.file=${MESH[m913k]} \
    --set output.checkpoint_interval=0.1e-6 --out "$out" > "$out.log" 2>&1
  python3 -c "
import json, os, glob
d = json.load(open('$out/summary.json')); sizes = [os.path.getsize(f) for f in sorted(glob.glob('$out/checkpoint_r*_g*.bin'))]
print('ckpt np$np', d['checkpoints_written'], 'rank0 bytes', d['checkpoint_bytes'], 'rank0 s', round(d['checkpoint_seconds'], 3), 'pieces', sizes, 'sum', sum(sizes))"
done
