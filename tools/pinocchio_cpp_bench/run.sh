#!/usr/bin/env bash
# Times Pinocchio 4.1 (C++, built by build.sh) on a URDF; prints the JSON of
# `articula bench --json` (nv, rnea_ns, crba_ns, aba_ns, rk4_step_ns) plus both conventions
# of crba and aba and the load check.
#
#   tools/pinocchio_cpp_bench/run.sh URDF [--floating] [--gravity x,y,z] [--batches N]
#
# The URDF is parsed by Pinocchio's own parser (Python bindings of the same C++ library) and
# handed over as a Boost text archive of the pinocchio::Model (export_model.py): the model the
# C++ program times is exactly the one Pinocchio builds from the URDF, and the program checks
# that its rnea reproduces Pinocchio-Python's at one state before timing.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
VENV="${PIN_VENV:-$HOME/.cache/pin-oracle}"
URDF="$1"; shift
EXPORT_ARGS=(); BATCHES=7
while [ $# -gt 0 ]; do
    case "$1" in
        --floating) EXPORT_ARGS+=(--floating) ;;
        --gravity) EXPORT_ARGS+=(--gravity "$2"); shift ;;
        --batches) BATCHES="$2"; shift ;;
        *) echo "unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
BIN="$(cd "$HERE/../.." && mkdir -p "${CARGO_TARGET_DIR:-target}" && cd "${CARGO_TARGET_DIR:-target}" && pwd)/pinocchio_bench"
[ -x "$BIN" ] || "$HERE/build.sh" "$VENV" >&2
TMP="$(mktemp -d)"; trap 'rm -rf "$TMP"' EXIT
"$VENV/bin/python" "$HERE/export_model.py" "$URDF" "$TMP/m" "${EXPORT_ARGS[@]}" >&2
"$BIN" "$TMP/m.model.txt" "$TMP/m.check.txt" "$BATCHES"
