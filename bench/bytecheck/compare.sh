#!/usr/bin/env bash
# Compares two bench/bytecheck/run.sh outputs: every CSV, VTU, PVTU, PVD and events file of
# every case, byte for byte (summary.json and logs hold wall times and are left out).
#   bash bench/bytecheck/compare.sh /tmp/bytes-main /tmp/bytes-new
set -uo pipefail
a=$1; b=$2; same=0; differ=0
while IFS= read -r f; do
  if cmp -s "$a/$f" "$b/$f"; then same=$((same + 1)); else echo "differs: $f"; differ=$((differ + 1)); fi
done < <(cd "$a" && find . -type f \( -name '*.csv' -o -name '*.vtu' -o -name '*.pvtu' -o -name '*.pvd' \) | sort)
echo "$same files equal, $differ differ"
[ "$differ" -eq 0 ]
