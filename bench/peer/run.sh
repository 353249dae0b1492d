#!/usr/bin/env bash
# bench/peer/run.sh: the glass branching plate (scenes/glass-branching.ini) in LAMMPS
# peridynamics and in brittle at matched resolution, side by side (issue 26, item 4).
#
# What it does, for each resolution h (lattice spacing = element size; default 0.5 mm):
#   1. brittle: the scene on a uniform mesh of size h (mesh.band = 0, one element layer through
#      the 0.5 mm thickness), one thread, to 80 us (run.stop_when_cut_through = false, so every
#      run reaches 80 us), one VTU frame at 80 us, then `brittle render` of its crack and
#      sigma1/sigma_c frames at 80 us.
#   2. LAMMPS: bench/peer/glass.lmp, the same plate as one layer of peridynamic atoms of
#      spacing h (bond-based PMB, horizon 3.015 h, 2D plane-stress calibration to E = 32 GPa
#      and G_c = 3 J/m^2; the constants come from bench/peer/peer.py params), its own stable
#      time step (0.8 x the Silling-Askari bound, --safety), one process, to 80 us, damage
#      dumped every 10 us and the crack's reach and spread logged every ~1 us (crack.csv).
#   3. LAMMPS again at brittle's (mean) time step, unless --no-matched-dt.
#   4. OUT/peer.md: one table (wall time to 80 us, peak RSS, updates/s, crack pattern), and
#      OUT/<h>/side_by_side.png: brittle's crack frame next to the LAMMPS damage at 80 us.
# Every simulation runs alone, single-threaded (run.threads=1, OMP_NUM_THREADS=1, one MPI
# process), under `nice -n 19`, timed by /usr/bin/time -v (wall, peak RSS).
# docs/peer.md has the measured table and how to read it. Not part of CI.
#
# Install (Debian 12; LAMMPS is an optional dependency of this script only):
#   apt-get install -y lammps python3-numpy python3-matplotlib time
#   lmp -h | grep -i peri          # the PERI package: pair styles peri/pmb, peri/lps, ...
# and a release build of brittle (cmake --preset release && cmake --build build/release).
#
# Usage (from anywhere; --out is relative to the current directory):
#   bash bench/peer/run.sh [0.5e-3|0.25e-3 ...] [--out DIR] [--reuse] [--no-matched-dt]
#                          [--safety F] [--nodal] [--2d]
#     sizes        element size = lattice spacing [m], any number of them (default 0.5e-3)
#     --out DIR    where everything goes (default <repo>/out/peer, git-ignored): DIR/peer.md,
#                  DIR/h<mm>mm/{brittle,lammps,lammps-matched-dt}/, DIR/h<mm>mm/side_by_side.png
#     --reuse      keep the runs already in DIR (re-read them, re-make table and pictures)
#     --no-matched-dt   skip the LAMMPS run at brittle's time step
#     --safety F   LAMMPS's own step as a fraction of its stable step (default 0.8; the crack's
#                  start, speed and branching converge from 0.4 down, docs/peer.md)
#     --nodal      brittle with the paper's nodal rule (scenes/glass-nodal.ini over the scene:
#                  how docs/peer.md's table was made); default: the scene as shipped (facet)
#     --2d         brittle's plate as a 2D body of triangles in plane stress
#                  (scenes/glass-branching-2d.ini over the scene; issue 53, docs/peer.md)
#     --ensemble N also brittle as an ensemble of N members varying the mesh realization
#                  (`brittle study ensemble --vary mesh`, docs/ensembles.md) at the same h:
#                  DIR/h<mm>mm/ensemble/ and DIR/h<mm>mm/ensemble_side_by_side.png, every
#                  member's crack next to the LAMMPS damage at 80 us
#     --set K=V    a scene key for brittle's runs (repeatable), e.g.
#                  --set fracture.criterion=coupled-facet
# Environment: BRITTLE (default build/release/app/brittle), LMP (default lmp),
#   PYTHON (default /usr/bin/python3: Debian's, with numpy and matplotlib).
# Cost on the 2-core AMD EPYC VM of docs/peer.md, one thread: 0.5 mm about 1.5 min in all
# (brittle 40 s, LAMMPS 6 s, LAMMPS at brittle's dt 35 s); 0.25 mm about 10 min (brittle 5 min,
# LAMMPS 35 s, at brittle's dt 3.6 min). Everything is deterministic: a rerun gives the same
# crack, only the times change.

set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
HERE="$ROOT/bench/peer"
BRITTLE="${BRITTLE:-$ROOT/build/release/app/brittle}"
LMP="${LMP:-lmp}"
PY="${PYTHON:-/usr/bin/python3}"
OUT="$ROOT/out/peer"
REUSE=0
MATCHED=1
SAFETY=0.8
SIZES=()
OVERLAY=()
ENSEMBLE=0
SETS=()

while [ $# -gt 0 ]; do
  case "$1" in
    --out) OUT="$2"; shift 2 ;;
    --out=*) OUT="${1#--out=}"; shift ;;
    --reuse) REUSE=1; shift ;;
    --no-matched-dt) MATCHED=0; shift ;;
    --safety) SAFETY="$2"; shift 2 ;;
    --safety=*) SAFETY="${1#--safety=}"; shift ;;
    --nodal) OVERLAY+=("$ROOT/scenes/glass-nodal.ini"); shift ;;
    --2d) OVERLAY+=("$ROOT/scenes/glass-branching-2d.ini"); shift ;;
    --ensemble) ENSEMBLE="$2"; shift 2 ;;
    --ensemble=*) ENSEMBLE="${1#--ensemble=}"; shift ;;
    --set) SETS+=(--set "$2"); shift 2 ;;
    --set=*) SETS+=(--set "${1#--set=}"); shift ;;
    -h|--help) sed -n '2,/^$/p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "run.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) SIZES+=("$1"); shift ;;
  esac
done
[ ${#SIZES[@]} -gt 0 ] || SIZES=(0.5e-3)

die() { echo "run.sh: $*" >&2; exit 1; }
[ -x "$BRITTLE" ] || die "no brittle binary at $BRITTLE (build the release preset, or set BRITTLE)"
command -v "$LMP" >/dev/null || die "no LAMMPS ('$LMP'): apt-get install -y lammps (or set LMP)"
"$LMP" -h 2>/dev/null | grep -c "peri/pmb" >/dev/null || die "$LMP has no PERI package (pair_style peri/pmb)"
[ -x /usr/bin/time ] || die "no /usr/bin/time: apt-get install -y time"
"$PY" -c 'import numpy, matplotlib' 2>/dev/null ||
  die "$PY lacks numpy/matplotlib: apt-get install -y python3-numpy python3-matplotlib"

mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"
SCENE="$ROOT/scenes/glass-branching.ini"
export OMP_NUM_THREADS=1

run_lammps() {  # DIR PARAMS.json-args...
  local dir="$1"; shift
  if [ "$REUSE" = 1 ] && grep -q "^Loop time" "$dir/log.lammps" 2>/dev/null; then
    echo "  reuse $dir"
  else
    rm -rf "$dir"; mkdir -p "$dir/dump"
    "$PY" "$HERE/peer.py" params "$@" --json "$dir/params.json" > "$dir/params.sh"
    # shellcheck disable=SC1091
    source "$dir/params.sh"
    echo "  LAMMPS: $P_atoms_expected atoms, dt = $P_dt s (dt_crit $P_dt_crit s), $P_nsteps steps"
    local skin
    skin="$("$PY" -c "print(0.5 * $P_h)")"
    (cd "$dir" && /usr/bin/time -v -o time.txt nice -n 19 "$LMP" -in "$HERE/glass.lmp" \
        -log log.lammps -screen none \
        -var h "$P_h" -var delta "$P_delta" -var L "$P_L" -var H "$P_H" -var T "$P_T" \
        -var a "$P_notch" -var rho "$P_rho" -var V "$P_V" -var c "$P_c" -var s0 "$P_s0" \
        -var fdens "$P_force_density" -var dt "$P_dt" -var nsteps "$P_nsteps" \
        -var dump_every "$P_dump_every" -var thermo_every "$P_thermo_every" -var dumpdir dump -var skin "$skin") ||
    die "LAMMPS failed: $dir/log.lammps"
  fi
  "$PY" "$HERE/peer.py" lammps-metrics "$dir/log.lammps" "$dir/time.txt" "$dir/dump" \
    "$dir/params.json" "$dir/metrics.json" > /dev/null
}

for h in "${SIZES[@]}"; do
  label="h$("$PY" -c "print('%g' % ($h * 1e3))")mm"
  base="$OUT/$label"
  mkdir -p "$base"
  echo "== $label"

  # 1. brittle
  b="$base/brittle"
  if [ "$REUSE" = 1 ] && [ -f "$b/run/summary.json" ] && [ -f "$b/time.txt" ]; then
    echo "  reuse $b"
  else
    rm -rf "$b"; mkdir -p "$b"
    cmd=("$BRITTLE" run "$SCENE" "${OVERLAY[@]}" --set "mesh.size=$h" --set mesh.band=0 --set mesh.layers=1
         --set run.threads=1 --set run.end_time=80e-6 --set run.stop_when_cut_through=false
         --set output.frame_times=80e-6 "${SETS[@]}" --out "$b/run")
    echo "  ${cmd[*]}" | sed "s|$ROOT/||g"
    printf '%q ' nice -n 19 "${cmd[@]}" > "$b/command.txt"
    /usr/bin/time -v -o "$b/time.txt" nice -n 19 "${cmd[@]}" > "$b/stdout.txt" 2>&1 ||
      die "brittle failed: $b/stdout.txt"
    nice -n 19 "$BRITTLE" render "$b/run" --times 80e-6 --fields crack,sigma1 \
      --set render.width=1000 --set render.height=480 --out "$b/render" > /dev/null 2>&1 ||
      die "brittle render failed"
  fi
  "$PY" "$HERE/peer.py" brittle-metrics "$b/run" "$b/time.txt" "$b/metrics.json" > /dev/null

  # 2. LAMMPS at its own stable step; 3. at brittle's mean step
  run_lammps "$base/lammps" --h "$h" --safety "$SAFETY"
  if [ "$MATCHED" = 1 ]; then
    bdt="$("$PY" -c "import json; m = json.load(open('$b/metrics.json')); print(m['dt'])")"
    echo "  LAMMPS at brittle's dt = $bdt s"
    run_lammps "$base/lammps-matched-dt" --h "$h" --dt "$bdt"
  fi

  # 4. the picture: brittle's crack frame, the LAMMPS damage (and at brittle's dt)
  crack_png="$(ls "$b"/render/crack_*us.png | tail -1)"
  dump_of() { "$PY" -c "import json; print(json.load(open('$1/metrics.json'))['final_dump'])"; }
  panels=(--lammps "$(dump_of "$base/lammps")" "LAMMPS peri/pmb, own dt: damage at 80 us")
  if [ "$MATCHED" = 1 ]; then
    panels+=(--lammps "$(dump_of "$base/lammps-matched-dt")" "LAMMPS peri/pmb, brittle's dt: damage at 80 us")
  fi
  "$PY" "$HERE/peer.py" picture --brittle "$crack_png" "${panels[@]}" \
    --params "$base/lammps/params.json" --out "$base/side_by_side.png" \
    --title "Glass plate at 80 us, h = $("$PY" -c "print('%g' % ($h * 1e3))") mm" \
    --brittle-title "brittle: crack faces (dark) and tips (red) at 80 us" > /dev/null

  # 5. the ensemble: every member's crack on one plate, next to the LAMMPS damage
  if [ "$ENSEMBLE" -gt 0 ]; then
    e="$base/ensemble"
    reuse_flag=(); [ "$REUSE" = 1 ] && reuse_flag=(--reuse)
    nice -n 19 "$BRITTLE" study ensemble "$SCENE" "${OVERLAY[@]}" --vary mesh --members "$ENSEMBLE" \
      --set "mesh.size=$h" --set mesh.band=0 --set mesh.layers=1 --set run.end_time=80e-6 \
      --set run.stop_when_cut_through=false "${SETS[@]}" "${reuse_flag[@]}" --out "$e" > "$base/ensemble.txt" 2>&1 ||
      die "brittle study ensemble failed: $base/ensemble.txt"
    "$PY" "$HERE/peer.py" picture --brittle "$e/ensemble.png" \
      --lammps "$(dump_of "$base/lammps")" "LAMMPS peri/pmb, own dt: damage at 80 us" \
      --params "$base/lammps/params.json" --out "$base/ensemble_side_by_side.png" \
      --title "Glass plate, h = $("$PY" -c "print('%g' % ($h * 1e3))") mm: brittle's ensemble and LAMMPS" \
      --brittle-title "brittle: $ENSEMBLE mesh realizations, every member's splits" > /dev/null
    grep "^forks:" "$base/ensemble.txt" | sed "s|^|  brittle ensemble: |"
  fi
done

"$PY" "$HERE/peer.py" table "$OUT" > /dev/null
echo "== $OUT/peer.md"
cat "$OUT/peer.md"
