#!/usr/bin/env bash
# The byte check (issue 39; docs/performance.md): runs the shipped scenes' cases with one
# brittle binary into OUT, one directory per case. Compare two binaries' outputs with
# bench/bytecheck/compare.sh OUT_A OUT_B (every CSV, VTU, PVTU, PVD and events file, byte for
# byte). Takes about 6 minutes on 2 cores. The last case (glass-mpi3, since issue 52) is the
# facet criterion on 3 ranks.
#   bash bench/bytecheck/run.sh build/release/app/brittle /tmp/bytes-new
set -euo pipefail
bin=$(realpath "$1"); out=$2
cd "$(dirname "$0")/../.."
mkdir -p "$out"
run() {  # NAME ARGS...
  local name=$1; shift
  rm -rf "${out:?}/$name"
  "$bin" run "$@" --out "$out/$name" > "$out/$name.log" 2>&1 || { echo "$name failed: $out/$name.log" >&2; return 1; }
  echo "$name done"
}
run cm-1thread scenes/cm.ini --set run.threads=1
run cm-2threads scenes/cm.ini --set run.threads=2
run rm-branching-damage scenes/rm.ini scenes/branching.ini scenes/damage.ini --set run.threads=2 --set run.end_time=15e-6
run rm-facet scenes/rm.ini scenes/branching.ini scenes/damage.ini scenes/rm-facet.ini --set run.threads=2 --set run.end_time=10e-6
run glass scenes/glass-branching.ini --set run.threads=2
run glass-nodal scenes/glass-branching.ini scenes/glass-nodal.ini --set run.threads=2 --set run.end_time=40e-6
run glass-energy scenes/glass-branching.ini scenes/glass-nodal.ini --set fracture.criterion=energy --set fracture.epsilon=1.5e-3 --set run.threads=2 --set run.end_time=35e-6
run kalthoff scenes/kalthoff.ini --set run.threads=2
# checkpoint at half-time, then resume from it to the end
run cm-checkpoint scenes/cm.ini --set run.threads=1 --set output.checkpoint_interval=5e-6 --set run.end_time=10e-6
"$bin" run --resume "$out/cm-checkpoint" --set run.end_time=20e-6 > "$out/cm-checkpoint-resume.log" 2>&1
echo "cm-checkpoint resumed"
rm -rf "$out/cm-mpi2"
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np 2 "$bin" run scenes/cm.ini --set run.threads=1 --out "$out/cm-mpi2" > "$out/cm-mpi2.log" 2>&1
echo "cm-mpi2 done"
rm -rf "$out/glass-mpi3"
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np 3 "$bin" run scenes/glass-branching.ini --set run.threads=1 --set mesh.band_size=1e-3 --set run.end_time=60e-6 --out "$out/glass-mpi3" > "$out/glass-mpi3.log" 2>&1
echo "glass-mpi3 done"
