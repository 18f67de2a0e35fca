"""Load a URDF with Pinocchio (its own C++ URDF parser, through the Python bindings) and save
the model as a Boost text archive for `pinocchio_bench` (tools/pinocchio_cpp_bench/bench.cpp),
plus one check row: a seeded random state and Pinocchio's rnea there, so the C++ program can
prove it loaded the same model.

    python export_model.py URDF OUT_PREFIX [--floating] [--gravity x,y,z]

Writes OUT_PREFIX.model.txt and OUT_PREFIX.check.txt (nq, nv, then q, v, a, tau on one line
each, %.17g).
"""
import argparse

import numpy as np
import pinocchio as pin

p = argparse.ArgumentParser()
p.add_argument("urdf")
p.add_argument("out")
p.add_argument("--floating", action="store_true")
p.add_argument("--gravity", default="0,0,-9.81")
args = p.parse_args()

if args.floating:
    model = pin.buildModelFromUrdf(args.urdf, pin.JointModelFreeFlyer())
else:
    model = pin.buildModelFromUrdf(args.urdf)
model.gravity.linear = np.array([float(x) for x in args.gravity.split(",")])
model.saveToText(args.out + ".model.txt")

rng = np.random.default_rng(3)
q = pin.neutral(model)
for j in model.joints[1:]:
    if j.nq == 1:
        q[j.idx_q] = rng.uniform(-np.pi, np.pi)
    elif j.shortname() == "JointModelFreeFlyer":
        q[j.idx_q : j.idx_q + 3] = rng.uniform(-0.5, 0.5, 3)
        x = rng.normal(size=4)
        q[j.idx_q + 3 : j.idx_q + 7] = x / np.linalg.norm(x)
    elif j.shortname() == "JointModelSpherical":
        x = rng.normal(size=4)
        q[j.idx_q : j.idx_q + 4] = x / np.linalg.norm(x)
v = rng.uniform(-1, 1, model.nv)
a = rng.uniform(-1, 1, model.nv)
tau = pin.rnea(model, model.createData(), q, v, a)
with open(args.out + ".check.txt", "w") as f:
    f.write(f"{model.nq} {model.nv}\n")
    for x in (q, v, a, tau):
        f.write(" ".join("%.17g" % e for e in x) + "\n")
kinds = sorted({j.shortname() for j in model.joints[1:]})
print(f"exported {args.urdf}: nq {model.nq}, nv {model.nv}, joints {', '.join(kinds)}")
