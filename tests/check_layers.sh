#!/usr/bin/env bash
# The layering rule of docs/architecture.md ("Layers"), checked over the quoted includes:
#   solver/physics < solver/mesh < solver/parallel < solver/run < solver/observers < render < app
# A file may include headers of its own layer and of the layers below it, never above.
#
#   bash tests/check_layers.sh [SOURCE_DIR]   one line per upward (or unknown) include, exit 1
#   bash tests/check_layers.sh --self-test    plants an upward include in a copy: must be caught
#   bash tests/check_layers.sh --libraries DIR   the same for symbols: no layer's library DIR/
#                                             libbrittle_LAYER.a needs a symbol only a higher one
#                                             defines (a member defined in the wrong folder)
set -euo pipefail

layers=(solver/physics solver/mesh solver/parallel solver/run solver/observers render app)

check() {
  local root=$1 bad=0 rank file line header found r
  declare -A layer_of  # header file name -> rank of the folder that holds it
  for r in "${!layers[@]}"; do
    for file in "$root/${layers[$r]}"/*.hpp; do
      [ -e "$file" ] && layer_of[$(basename "$file")]=$r
    done
  done
  layer_of[build_info.hpp]=4  # solver/build_info.hpp: generated with the observers' library
  for rank in "${!layers[@]}"; do
    for file in "$root/${layers[$rank]}"/*.hpp "$root/${layers[$rank]}"/*.cpp; do
      [ -e "$file" ] || continue
      while IFS=: read -r line header; do
        header=${header#*\"}; header=${header%%\"*}
        found=${layer_of[$(basename "$header")]:-}
        if [ -z "$found" ]; then
          echo "${file#"$root"/}:$line: #include \"$header\" is in no layer (${layers[*]})"
          bad=1
        elif [ "$found" -gt "$rank" ]; then
          echo "${file#"$root"/}:$line: #include \"$header\" points up, from ${layers[$rank]}" \
               "to ${layers[$found]} (docs/architecture.md, Layers)"
          bad=1
        fi
      done < <(grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$file" | cut -d: -f1,2- || true)
    done
  done
  return $bad
}

if [ "${1:-}" = "--libraries" ]; then
  libs=(physics mesh parallel run observers) dir=$2 bad=0
  for low in 0 1 2 3; do
    for high in $(seq $((low + 1)) 4); do
      while read -r symbol; do
        echo "libbrittle_${libs[$low]}.a needs $symbol, defined in libbrittle_${libs[$high]}.a"
        bad=1
      done < <(comm -12 <(nm -C -u "$dir/libbrittle_${libs[$low]}.a" | sed 's/^ *U //' | sort -u) \
                        <(nm -C --defined-only "$dir/libbrittle_${libs[$high]}.a" |
                          awk '$2 ~ /^[TDBR]$/ { $1 = ""; $2 = ""; sub(/^  /, ""); print }' | sort -u))
    done
  done
  [ $bad = 0 ] && echo "layers: no library needs a symbol of a layer above it"
  exit $bad
fi
if [ "${1:-}" = "--self-test" ]; then
  here=$(cd "$(dirname "$0")/.." && pwd)
  tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
  for d in "${layers[@]}"; do mkdir -p "$tmp/$d" && cp "$here/$d"/*.[ch]pp "$tmp/$d/"; done
  check "$tmp" > /dev/null || { echo "self-test: the clean copy does not pass" >&2; exit 1; }
  printf '#include "simulation.hpp"\n' >> "$tmp/solver/physics/material.cpp"
  if out=$(check "$tmp"); then echo "self-test: an upward include went unnoticed" >&2; exit 1; fi
  grep -q '^solver/physics/material.cpp:[0-9]*: #include "simulation.hpp" points up' <<<"$out" \
    || { echo "self-test: unexpected report: $out" >&2; exit 1; }
  echo "self-test: the planted include was caught: $out"
  exit 0
fi
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
check "$root" && echo "layers: every include points down (${layers[*]})"
