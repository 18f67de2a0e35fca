#!/usr/bin/env bash
# articula vs Pinocchio 4.1 C++ (-O3 -march=native), model by model, back to back in one run:
# `articula bench --json` (release build) and tools/pinocchio_cpp_bench/run.sh on the same
# model, then a table of ns per call and the ratio articula / Pinocchio (< 1: articula faster).
#
#   tools/bench_side_by_side.sh [REAL_TAKES_DIR]      # default ../shared/data/bvh
#
# Both binaries live in cargo's target directory: $CARGO_TARGET_DIR when set (relative to the
# repository if relative, as cargo takes it), else target/.
# Models: UR5 and TALOS from example-robot-data (installed with Pinocchio), data/arm7.urdf and data/humanoid.urdf (fixed base, gravity 0,0,-9.81, both sides read
# the same URDF); data/demo_walk.bvh and REAL_TAKES_DIR/cmu_01_01.bvh (if present) in the euler
# joint model: articula builds the model from the BVH (default options: 75 kg male, de Leva),
# Pinocchio reads the URDF that `articula export urdf` writes for that take (same model, same
# joint order, fixed base with the `world` link as root, gravity 0,-9.81,0: both takes are Y-up;
# tests/dynamics_take_urdf.rs proves the two agree to 1e-10), as tools/take_urdf_fixtures.sh.
# Both sides: 16 random states (revolute angles uniform in [-pi, pi), prismatic in [-0.5, 0.5),
# v and a uniform in [-1, 1), tau = 0 for aba), batches of at least 2 ms, median of BATCHES
# (default 7; more ride out a busy machine) batches. Set PIN_VENV for another Pinocchio venv.
set -euo pipefail
cd "$(dirname "$0")/.."
REAL="${1:-../shared/data/bvh}"
BATCHES="${BATCHES:-7}"
TARGET="${CARGO_TARGET_DIR:-target}"
cargo build -q --release
[ -x "$TARGET/pinocchio_bench" ] || tools/pinocchio_cpp_bench/build.sh >&2
TMP="$(mktemp -d)"; trap 'rm -rf "$TMP"' EXIT
run() {  # name, articula args, pinocchio urdf, pinocchio args
    local name="$1" a="$2" urdf="$3" p="$4"
    # shellcheck disable=SC2086
    "$TARGET/release/articula" bench $a --json --batches "$BATCHES" > "$TMP/$name.articula.json"
    # shellcheck disable=SC2086
    tools/pinocchio_cpp_bench/run.sh "$urdf" $p --batches "$BATCHES" > "$TMP/$name.pinocchio.json" 2>/dev/null
    echo "$name" >> "$TMP/order"
}
# Pinocchio's own benchmark robots (example-robot-data, in the Pinocchio venv): UR5 (fixed
# base, nv 6) and TALOS (talos_full_v2, floating base, nv 50), the models issue 17 names
ERD="$(echo "${PIN_VENV:-$HOME/.cache/pin-oracle}"/lib/python3*/site-packages/cmeel.prefix/share/example-robot-data/robots)"
if [ -d "$ERD" ]; then
    run ur5 "--urdf $ERD/ur_description/urdf/ur5_robot.urdf" "$ERD/ur_description/urdf/ur5_robot.urdf" ""
    run talos "--urdf $ERD/talos_data/robots/talos_full_v2.urdf --floating" \
        "$ERD/talos_data/robots/talos_full_v2.urdf" "--floating"
else
    echo "SKIPPED ur5 and talos: no example-robot-data in the Pinocchio venv" >&2
fi
run arm7 "--urdf data/arm7.urdf" data/arm7.urdf ""
run humanoid "--urdf data/humanoid.urdf" data/humanoid.urdf ""
"$TARGET/release/articula" export urdf data/demo_walk.bvh -o "$TMP/demo_walk.urdf" 2>/dev/null
run demo_walk "data/demo_walk.bvh" "$TMP/demo_walk.urdf" "--gravity 0,-9.81,0"
if [ -f "$REAL/cmu_01_01.bvh" ]; then
    "$TARGET/release/articula" export urdf "$REAL/cmu_01_01.bvh" -o "$TMP/cmu_01_01.urdf" 2>/dev/null
    run cmu_01_01 "$REAL/cmu_01_01.bvh" "$TMP/cmu_01_01.urdf" "--gravity 0,-9.81,0"
fi
python3 - "$TMP" <<'PYEOF'
import json, os, sys
d = sys.argv[1]
keys = ["rnea_ns", "crba_ns", "aba_ns", "rk4_step_ns"]
print("load average: " + " ".join(open("/proc/loadavg").read().split()[:3]))
print(f"{'model':<11} {'nv':>3}  " + "  ".join(f"{k[:-3]:>24}" for k in keys))
print(f"{'':<11} {'':>3}  " + "  ".join(f"{'articula / pin = ratio':>24}" for _ in keys))
for name in open(os.path.join(d, "order")).read().split():
    a = json.load(open(os.path.join(d, name + ".articula.json")))
    p = json.load(open(os.path.join(d, name + ".pinocchio.json")))
    assert a["nv"] == p["nv"], f"{name}: nv {a['nv']} vs {p['nv']}"
    cells = [f"{a[k]/1e3:8.2f} / {p[k]/1e3:6.2f} = {a[k]/p[k]:4.2f}" for k in keys]
    print(f"{name:<11} {a['nv']:>3}  " + "  ".join(f"{c:>24}" for c in cells))
print("(µs per call; Pinocchio crba/aba: the faster of its LOCAL and WORLD conventions; crba "
      "fills the upper triangle in Pinocchio, the full matrix in articula)")
PYEOF
