#!/usr/bin/env bash
# Builds pinocchio_bench (bench.cpp) against Pinocchio 4.1's headers from the pip install
# (`pin` in the oracle venv; Eigen from `pip install cmeel-eigen` into the same venv).
#
#   tools/pinocchio_cpp_bench/build.sh [VENV]     # VENV default ~/.cache/pin-oracle
#
# Flags: -O3 -march=native -DNDEBUG. Every timed Pinocchio function is compiled here from the
# headers (no PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION, so nothing comes precompiled from
# libpinocchio_default.so); only Boost.Serialization is linked, to read the model archive.
# Writes pinocchio_bench next to cargo's output: in $CARGO_TARGET_DIR when set (relative to
# the repository if relative), else in the repository's target/.
set -euo pipefail
VENV="${1:-$HOME/.cache/pin-oracle}"
PREFIX="$(echo "$VENV"/lib/python3*/site-packages/cmeel.prefix)"
[ -d "$PREFIX/include/pinocchio" ] || { echo "no Pinocchio headers under $PREFIX" >&2; exit 1; }
if [ ! -d "$PREFIX/include/eigen3/Eigen" ]; then
    echo "Eigen headers missing: $VENV/bin/pip install cmeel-eigen" >&2; exit 1
fi
HERE="$(cd "$(dirname "$0")" && pwd)"
OUT="$(cd "$HERE/../.." && mkdir -p "${CARGO_TARGET_DIR:-target}" && cd "${CARGO_TARGET_DIR:-target}" && pwd)/pinocchio_bench"
mkdir -p "$(dirname "$OUT")"
# the compile definitions Pinocchio's CMake config gives its users (pinocchioTargets.cmake),
# minus the template instantiation one
DEFS="-DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12"
g++ -std=c++17 -O3 -march=native -DNDEBUG $DEFS \
    -isystem "$PREFIX/include" -isystem "$PREFIX/include/eigen3" \
    "$HERE/bench.cpp" -o "$OUT" \
    -L"$PREFIX/lib" -Wl,-rpath,"$PREFIX/lib" -lboost_serialization
echo "$OUT"
