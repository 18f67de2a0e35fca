#!/usr/bin/env bash
# Issue 17's workbench figures for one or more articula binaries, alternating binaries within
# each round so that they see the same machine: the stages of a take cycled to a minute (one and
# two threads), a mass edit without and with contact, and a smoothing edit. Min / median ms, as
# `articula bench` prints them. Run on a quiet machine; compare the rounds' minima.
#
#   tools/bench_issue17.sh [ROUNDS] BIN [BIN…]      (TAKE=path, default ../shared/data/bvh/cmu_01_01.bvh)
set -euo pipefail
rounds=1
if [[ "${1:-}" =~ ^[0-9]+$ ]]; then rounds=$1; shift; fi
[ $# -ge 1 ] || { echo "usage: $0 [ROUNDS] BIN [BIN…]" >&2; exit 2; }
take="${TAKE:-$(dirname "$0")/../../shared/data/bvh/cmu_01_01.bvh}"
[ -f "$take" ] || { echo "$0: no take at $take (set TAKE)" >&2; exit 2; }
edit() { grep -oE 'min [0-9.]+ ms, median [0-9.]+ ms' | head -1; }
for _ in $(seq "$rounds"); do
  for bin in "$@"; do
    for t in 1 2; do
      echo "$bin stages t$t: $("$bin" bench --stages "$take" --minutes 1 --repeat 7 --threads "$t" --contact none \
        | grep -E '^(parse|model|coordinates|unwrap|smooth|derivatives|inverse|total)' \
        | awk '{printf "%s %s/%s  ", $1, $2, $3}')"
    done
    echo "$bin mass-none t1: $("$bin" bench "$take" --edit body.mass=80,70 --contact none --threads 1 --repeat 15 | edit)"
    for t in 1 2; do
      echo "$bin contact t$t: $("$bin" bench "$take" --edit body.mass=80,70 --contact feet --set consistent=off --threads "$t" --repeat 15 | edit)"
    done
    echo "$bin smooth-edit t1: $("$bin" bench "$take" --edit smooth=butterworth:5hz,butterworth:6hz --contact none --threads 1 --repeat 15 | edit)"
  done
done
