#!/usr/bin/env bash
# Checks that the paper's Figs. 5-6 still come out of the code as docs/figures/fit_errors.txt
# records them (docs/reproduction.md, "Checking the record"):
#
#   bash bench/reproduce/check.sh [--brittle EXE] [--expected FILE] [--tolerance POINTS] [--fresh FILE]
#
# runs `brittle reproduce --frames no` (about 2-4 minutes on 2 cores) unless --fresh names the
# fit_errors.txt of a run already made, and compares every curve's mean error with FILE (default
# docs/figures/fit_errors.txt). A curve further than POINTS percentage points (default 0.2, above
# the round-off ensemble's spread of docs/reproduction.md) from the record, or missing on either
# side, is printed and makes the exit status 1. --self-test: the comparison passes on the record
# itself and fails on a copy with one curve 0.3 points off (ctest RecordCheck.CatchesADoctoredCurve).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
brittle=$root/build/release/app/brittle expected=$root/docs/figures/fit_errors.txt
tolerance=0.2 fresh=
while [ $# -gt 0 ]; do
  case $1 in
    --brittle) brittle=$2; shift 2 ;;
    --expected) expected=$2; shift 2 ;;
    --tolerance) tolerance=$2; shift 2 ;;
    --fresh) fresh=$2; shift 2 ;;
    --self-test)  # the comparison on the record itself (holds) and on a doctored copy (fails)
      tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
      awk '/calibrated/ { sub(/[0-9.]+ %$/, ($(NF - 1) + 0.3) " %") } 1' "$expected" > "$tmp/doctored.txt"
      bash "$0" --expected "$expected" --fresh "$expected" > /dev/null ||
        { echo "self-test: the record does not match itself" >&2; exit 1; }
      if out=$(bash "$0" --expected "$expected" --fresh "$tmp/doctored.txt"); then
        echo "self-test: a curve 0.3 points off went unnoticed" >&2; exit 1
      fi
      grep -q 'calibrated.*DIFFERS' <<<"$out" || { echo "self-test: unexpected report: $out" >&2; exit 1; }
      echo "self-test: the doctored curve was caught"; exit 0 ;;
    *) echo "check.sh: unknown option '$1' (expected --brittle, --expected, --tolerance, --fresh)" >&2
       exit 2 ;;
  esac
done
[ -r "$expected" ] || { echo "check.sh: --expected '$expected': no such file" >&2; exit 2; }
if [ -z "$fresh" ]; then
  out=$(mktemp -d); trap 'rm -rf "$out"' EXIT
  "$brittle" reproduce --out "$out" --frames no > "$out/reproduce.log" 2>&1 ||
    { tail -5 "$out/reproduce.log" >&2; echo "check.sh: brittle reproduce failed" >&2; exit 1; }
  fresh=$out/fit_errors.txt
fi
# "Fig. 6b (damage):" heads a block; "  RD-RM calibrated  mean ...: 3.9 %" is one curve.
table() {
  awk '/^Fig/ { fig = $1 " " $2 } /mean \|v/ { name = $0; sub(/ +mean.*/, "", name);
       sub(/^ +/, "", name); value = $(NF - 1); print fig " " name "\t" value }' "$1"
}
awk -F'\t' -v tol="$tolerance" '
  NR == FNR { want[$1] = $2; order[++n] = $1; next }
  { got[$1] = $2 }
  END {
    bad = 0
    for (i = 1; i <= n; ++i) {
      k = order[i]
      if (!(k in got)) { printf "%s: in the record (%s %%), not in the fresh run\n", k, want[k]; bad = 1; continue }
      d = got[k] - want[k]; if (d < 0) d = -d
      status = d > tol + 1e-9 ? "DIFFERS" : "ok"
      if (d > tol + 1e-9) bad = 1
      printf "%-32s record %5.1f %%  fresh %5.1f %%  %s\n", k, want[k], got[k], status
    }
    for (k in got) if (!(k in want)) { printf "%s: in the fresh run, not in the record\n", k; bad = 1 }
    printf "fit errors: %s (tolerance %s points)\n", bad ? "the record does not hold" : "the record holds", tol
    exit bad
  }' <(table "$expected") <(table "$fresh")
