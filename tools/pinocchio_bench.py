"""Side-by-side speed reference: Pinocchio's rnea, crba, aba per call (ns, median of batches)
through its Python bindings, on the same URDFs `articula bench` times.

    $PY tools/pinocchio_bench.py data/arm7.urdf data/humanoid.urdf model.urdf [--gravity 0,-9.81,0]

The bindings add a call overhead (~0.3-1 µs) that the C++ library itself does not pay, so for
small models these numbers are an upper bound on Pinocchio's C++ time.
"""
import sys, time, statistics
import numpy as np
import pinocchio as pin

def bench(path, gravity):
    m = pin.buildModelFromUrdf(path)
    m.gravity.linear = np.array(gravity)
    d = m.createData()
    rng = np.random.default_rng(42)
    qs = [pin.randomConfiguration(m, -np.ones(m.nq), np.ones(m.nq)) for _ in range(16)]
    vs = [rng.uniform(-1, 1, m.nv) for _ in range(16)]
    As = [rng.uniform(-1, 1, m.nv) for _ in range(16)]
    out = {}
    for name, f in [
        ("rnea", lambda i: pin.rnea(m, d, qs[i], vs[i], As[i])),
        ("crba", lambda i: pin.crba(m, d, qs[i])),
        ("aba", lambda i: pin.aba(m, d, qs[i], vs[i], As[i])),
    ]:
        per = []
        for _ in range(7):
            n = 0
            t0 = time.perf_counter()
            while time.perf_counter() - t0 < 0.05:
                for i in range(16):
                    f(i)
                n += 16
            per.append((time.perf_counter() - t0) / n * 1e9)
        out[name] = statistics.median(per)
    return m.nv, out

g = [0, 0, -9.81]
paths = []
for a in sys.argv[1:]:
    if a.startswith("--gravity="):
        g = [float(x) for x in a.split("=")[1].split(",")]
    else:
        paths.append(a)
for p in paths:
    nv, r = bench(p, g)
    print(f"{p} (nv {nv}): " + "  ".join(f"{k} {v:.0f} ns" for k, v in r.items()))
