#!/usr/bin/env bash
# bench/step/mesh_options.sh: how Gmsh's options shape the stable step of the glass plate of
# bench/peer (uniform h = 0.5 mm; issue 38, item 2; docs/performance.md, "Better elements").
# Builds mesh_options.cpp (g++ and libgmsh-dev), meshes the plate once per variant and prints
# `brittle run --dry-run`'s step distribution in h / c_p (glass: c_p = 3810 m/s) as a Markdown
# table: the elements' altitude-bound steps at cfl 0.5 (the safe cfl of that bound) and the
# nodal bound at cfl 1 (its limit), with the scene's viscosity and without it. About a minute.
#
#   bash bench/step/mesh_options.sh [--brittle EXE]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
brittle=$root/build/release/app/brittle
[ "${1:-}" = --brittle ] && brittle=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
g++ -O1 -std=c++20 "$root/bench/step/mesh_options.cpp" -o "$tmp/mesh_options" -lgmsh
# The glass scene without its [notch.left] (the mesh file carries the notch).
python3 - "$root/scenes/glass-branching.ini" "$tmp/glass.ini" <<'PY'
import re, sys
s = open(sys.argv[1]).read()
s = re.sub(r'\[notch\.left\].*?(?=\n\[)', '', s, flags=re.S)
s = re.sub(r'\[mesh\].*?(?=\n\[)', '[mesh]\n', s, flags=re.S)
open(sys.argv[2], 'w').write(s)
PY
echo "| variant | tets | dt_e at cfl 0.5: smallest | 1st percentile | median | within 10 % | smallest altitude / h | nodal bound at cfl 1 | the same undamped |"
echo "|---|---|---|---|---|---|---|---|---|"
# name: H ALG2D LAYERS ALG3D SMOOTHING OPTIMIZE NETGEN THRESHOLD
while read -r name args; do
  if ! "$tmp/mesh_options" "$tmp/m.msh" $args > "$tmp/gen.log" 2>&1; then
    echo "| $name | Gmsh failed: $(tail -c 120 "$tmp/gen.log" | tr '\n|' '  ') | | | | | | | |"; continue
  fi
  if ! "$brittle" run "$tmp/glass.ini" --set mesh.file="$tmp/m.msh" --set run.cfl=0.5 \
      --dry-run --out "$tmp/x" > "$tmp/dry.txt" 2>&1; then
    echo "| $name | refused: $(tail -c 200 "$tmp/dry.txt" | tr '\n|' '  ') | | | | | | | |"; continue
  fi
  python3 - "$name" "$tmp/dry.txt" <<'PY'
import re, sys
t = open(sys.argv[2]).read(); hc = 0.5e-3 / 3810.0
def f(p):
    m = re.search(p, t)
    if not m:
        print('| %s | no step distribution: %s | | | | | | | |' % (sys.argv[1], t.strip().splitlines()[-1][:200]))
        sys.exit(0)
    return float(m.group(1))
print('| %s | %d | %.3f | %.3f | %.3f | %d | %.2f | %.3f | %.3f |' % (sys.argv[1],
      f(r'mesh\s+(\d+) tets'), f(r'dt_e\s+smallest ([0-9.e+-]+)') / hc,
      f(r'1st percentile ([0-9.e+-]+)') / hc, f(r'median ([0-9.e+-]+)') / hc,
      f(r'(\d+) elements? within'), f(r'altitude ([0-9.e+-]+) mm \(') / 0.5,
      2 * f(r'dt_nodal\s+([0-9.e+-]+)') / hc, 2 * f(r'([0-9.e+-]+) s without the viscosity') / hc))
PY
done <<'VARIANTS'
frontal-delaunay,1-layer 0.5e-3 6 1 1 1 1 0 0.3
delaunay,1-layer 0.5e-3 5 1 1 1 1 0 0.3
meshadapt,1-layer 0.5e-3 1 1 1 1 1 0 0.3
frontal-delaunay,smoothing-10 0.5e-3 6 1 1 10 1 0 0.3
delaunay,smoothing-10 0.5e-3 5 1 1 10 1 0 0.3
frontal-delaunay,netgen 0.5e-3 6 1 1 1 1 1 0.3
frontal-delaunay,threshold-0.6 0.5e-3 6 1 1 1 1 0 0.6
frontal-delaunay,2-layers 0.5e-3 6 2 1 1 1 0 0.3
free,delaunay-3d 0.5e-3 6 0 1 1 1 0 0.3
free,delaunay-3d,netgen 0.5e-3 6 0 1 1 1 1 0.3
free,hxt 0.5e-3 6 0 10 1 1 0 0.3
free,hxt,threshold-0.6 0.5e-3 6 0 10 1 1 0 0.6
free,frontal-3d 0.5e-3 6 0 4 1 1 0 0.3
VARIANTS
