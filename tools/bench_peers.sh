#!/usr/bin/env bash
# articula against the peer that does the same job, stage by stage, measured in one run
# (issue 17 item 7), one table with ratios (articula / peer: < 1 means articula is faster):
#
#   parse      `articula bench --stages` parse (BVH text in memory → joints and frames)
#              vs pybvh's read_bvh_file (PyPI `pybvh`, file in the page cache) and three.js's
#              BVHLoader.parse (npm `three`, text in memory, under node)
#   smooth     articula's smooth stage (Butterworth, default 6 Hz, order 2 each way, every
#              coordinate of the euler model) vs SciPy's signal.filtfilt with butter(2, 6 Hz)
#              on the take's channel matrix (frames × channels: the same samples and columns)
#   kernels    rnea / crba / aba / one RK4 step against Pinocchio C++ on UR5 and TALOS, by
#              tools/bench_side_by_side.sh (its own table; skipped with PEERS_KERNELS=0)
#
#   tools/bench_peers.sh [TAKE]        # default ../shared/data/bvh/cmu_01_01.bvh; REPEAT=7
#
# Medians over REPEAT runs each side, one thread, no contact (`--threads 1 --contact none`).
# The peers are installed under PEERS_DIR (default /tmp/articula-peers): a venv with pybvh,
# scipy and numpy, an npm prefix with three. Without network a peer that cannot be installed
# is SKIPPED with a message, never silently. Run on a quiet machine: the printed load average
# says how quiet it was.
set -euo pipefail
cd "$(dirname "$0")/.."
TAKE="${1:-../shared/data/bvh/cmu_01_01.bvh}"
REPEAT="${REPEAT:-7}"
DIR="${PEERS_DIR:-/tmp/articula-peers}"
[ -f "$TAKE" ] || { echo "no take $TAKE" >&2; exit 2; }
cargo build -q --release
BIN="${CARGO_TARGET_DIR:-target}/release/articula"
mkdir -p "$DIR"
TMP="$(mktemp -d)"; trap 'rm -rf "$TMP"' EXIT

# the peers (each one skipped loudly when it cannot be installed)
PY=""
if [ -x "$DIR/venv/bin/python" ] || python3 -m venv "$DIR/venv" >&2; then
    if "$DIR/venv/bin/python" -c 'import pybvh, scipy, numpy' 2>/dev/null ||
        "$DIR/venv/bin/pip" install -q pybvh scipy numpy >&2; then
        PY="$DIR/venv/bin/python"
    fi
fi
[ -n "$PY" ] || echo "SKIPPED pybvh and SciPy: could not install them into $DIR/venv (network?)" >&2
NODE=""
if command -v node >/dev/null && { [ -d "$DIR/npm/node_modules/three" ] ||
    npm install --silent --prefix "$DIR/npm" three >&2; }; then
    NODE=node
else
    echo "SKIPPED three.js: no node, or npm could not install three into $DIR/npm (network?)" >&2
fi

# articula: the stages of `id`, medians
"$BIN" bench --stages "$TAKE" --repeat "$REPEAT" --threads 1 --contact none --json > "$TMP/articula.json"

# pybvh and SciPy
if [ -n "$PY" ]; then
    "$PY" - "$TAKE" "$REPEAT" > "$TMP/python.json" <<'PYEOF'
import json, sys, time, warnings
import numpy as np
from scipy import signal
import pybvh
path, repeat = sys.argv[1], int(sys.argv[2])
def median_ms(f):
    t = []
    for _ in range(repeat + 1):  # one untimed warm-up, as articula's
        t0 = time.perf_counter(); f(); t.append(time.perf_counter() - t0)
    return float(np.median(t[1:]) * 1e3)
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    parse = median_ms(lambda: pybvh.read_bvh_file(path))
# the channel matrix, as the file gives it (degrees and file units: filtering is linear)
text = open(path).read().split("\n")
k = next(i for i, l in enumerate(text) if l.strip().startswith("Frame Time"))
dt = float(text[k].split(":")[1])
x = np.array([[float(v) for v in l.split()] for l in text[k + 1:] if l.strip()])
b, a = signal.butter(2, 6.0 / (0.5 / dt))
smooth = median_ms(lambda: signal.filtfilt(b, a, x, axis=0))
print(json.dumps({"parse_ms": parse, "smooth_ms": smooth, "frames": x.shape[0], "channels": x.shape[1]}))
PYEOF
fi

# three.js
if [ -n "$NODE" ]; then
    cat > "$TMP/three.mjs" <<'JSEOF'
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
const [dir, take, repeat] = process.argv.slice(2);
const { BVHLoader } = await import(pathToFileURL(join(dir, 'node_modules/three/examples/jsm/loaders/BVHLoader.js')).href);
const text = readFileSync(take, 'utf8');
const t = [];
for (let k = 0; k <= Number(repeat); k++) {
  const t0 = process.hrtime.bigint();
  new BVHLoader().parse(text);
  t.push(Number(process.hrtime.bigint() - t0) / 1e6);
}
const s = t.slice(1).sort((a, b) => a - b);
console.log(JSON.stringify({ parse_ms: s[Math.floor(s.length / 2)] }));
JSEOF
    node "$TMP/three.mjs" "$DIR/npm" "$TAKE" "$REPEAT" > "$TMP/three.json"
fi

python3 - "$TMP" "$TAKE" <<'PYEOF'
import json, os, sys
d, take = sys.argv[1], sys.argv[2]
a = json.load(open(os.path.join(d, "articula.json")))
load = lambda n: json.load(open(os.path.join(d, n))) if os.path.exists(os.path.join(d, n)) else None
py, js = load("python.json"), load("three.json")
print("load average: " + " ".join(open("/proc/loadavg").read().split()[:3]))
print(f"take {os.path.basename(take)}: {a['frames']} frames, nv {a['nv']}; ms, median of {a['repeat']}")
print(f"{'stage':<8} {'articula':>9}  {'peer':<32} {'peer':>9}  {'ratio':>6}")
rows = [("parse", "parse", "pybvh read_bvh_file", py, "parse_ms"),
        ("parse", "parse", "three.js BVHLoader.parse", js, "parse_ms"),
        ("smooth", "smooth", "SciPy filtfilt butter(2, 6 Hz)", py, "smooth_ms")]
for stage, key, peer, p, pk in rows:
    mine = a["stages_ms"][key]
    if p is None:
        print(f"{stage:<8} {mine:>9.2f}  {peer:<32} {'SKIPPED':>9}")
    else:
        print(f"{stage:<8} {mine:>9.2f}  {peer:<32} {p[pk]:>9.2f}  {mine / p[pk]:>6.3f}")
if py:
    print(f"(SciPy filtered {py['frames']} × {py['channels']} channel values; articula every "
          f"coordinate of the model)")
PYEOF

if [ "${PEERS_KERNELS:-1}" != 0 ]; then
    tools/bench_side_by_side.sh "$(dirname "$TAKE")"
fi
