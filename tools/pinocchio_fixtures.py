#!/usr/bin/env python3
"""Golden dynamics fixtures from Pinocchio for any URDF.

Run with the Pinocchio oracle venv (see tools/README.md):

    PY=$(bash ../shared/oracle/setup.sh)           # or ~/.cache/pin-oracle/bin/python
    $PY tools/pinocchio_fixtures.py                # the default set (arm7, humanoid, humanoid_floating)
    $PY tools/pinocchio_fixtures.py --model data/arm7.urdf --name arm7 \\
                                    --model take.urdf --floating --gravity 0,-9.81,0 --name take

Each `--model FILE` starts a model; `--floating`, `--name NAME` (default: the file's stem, plus
`_floating`), `--gravity x,y,z` (default 0,0,-9.81), `--rows N` (default 8) and `--seed S`
(default: derived from the name) that follow it apply to that model. Writes
`<out>/<name>/` (default out: tests/fixtures/pinocchio):

  model.json   nq, nv, gravity, joints in Pinocchio order (type, idx_q, idx_v, parent), the
               q / v column names, total mass, frames written by fk.csv, versions
  states.csv   q:<..> v:<..> a:<..> tau:<..>  (one state per row)
  rnea.csv     tau:<dof>       inverse dynamics of (q, v, a)
  crba.csv     M:<i>:<j>       joint-space inertia, full symmetric, row-major, Pinocchio dof order
  aba.csv      a:<dof>         forward dynamics of (q, v, tau)
  gravity.csv  g:<dof>         generalized gravity g(q)
  nle.csv      nle:<dof>       C(q, v) v + g(q)
  fk.csv       <joint>:x,y,z for every joint frame, then <body>:x,y,z,r00..r22 for every body
               (link) frame, world coordinates (r<i><j> = row i, column j of the world rotation)
  energy.csv   kinetic, potential, total, com:x, com:y, com:z

Column names follow ../shared/oracle/pin_ref.py (1-DoF joint `q:<joint>`; free flyer
`q:<joint>:x y z qx qy qz qw` with w last, root position in world, `v:<joint>:vx vy vz wx wy wz`
in the root's local frame, linear first; spherical `qx qy qz qw` / `wx wy wz`; continuous
`cos sin` / one column). Numbers with 17 significant digits. Row 0 of every model is the
neutral configuration (clamped into the joint limits) at rest with zero torque; row 1 is a
random configuration at rest (v = a = 0); the other rows are random throughout.

Random states (seeded, reproducible): q uniform within the joint limits (shrunk by 5 %; +-pi
where a joint has none), free-flyer position uniform in a 1 m box and a uniformly random unit
quaternion, v ~ N(0, 1) rad/s or m/s, a ~ N(0, 2^2), tau = g(q) + diag(M(q)) * N(0, 1).
The script also checks Pinocchio against itself (M column j == rnea(e_j) - nle, aba(rnea(a)) == a,
M symmetric positive definite) and stops if that fails.
"""
import json
import os
import sys
import zlib

import numpy as np
import pinocchio as pin

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
DEFAULT = [
    ["--model", "data/arm7.urdf", "--name", "arm7"],
    ["--model", "data/humanoid.urdf", "--name", "humanoid"],
    ["--model", "data/humanoid.urdf", "--floating", "--name", "humanoid_floating"],
]


# ----------------------------------------------------------------------------- arguments
def parse_args(argv):
    """Per-model options: every `--model` starts a new spec; the options after it belong to it."""
    usage = __doc__.split("\n\n")[1]
    out, specs, cur = os.path.join(ROOT, "tests", "fixtures", "pinocchio"), [], None
    glob = {"gravity": "0,0,-9.81", "rows": 8, "seed": None}
    it = iter(argv)
    for a in it:
        if a in ("-h", "--help"):
            print(__doc__)
            sys.exit(0)
        elif a == "--out":
            out = next(it)
        elif a == "--model":
            cur = dict(glob, model=next(it), floating=False, name=None)
            specs.append(cur)
        elif a in ("--floating", "--name", "--gravity", "--rows", "--seed"):
            key = a[2:]
            val = True if a == "--floating" else next(it)
            if cur is None:
                if key in ("floating", "name"):
                    sys.exit(f"{a} must follow a --model\n{usage}")
                glob[key] = val
            else:
                cur[key] = val
        else:
            sys.exit(f"unknown argument {a!r}\n{usage}")
    if not specs:  # the default set, with any global options given
        return parse_args(list(argv) + [t for d in DEFAULT for t in d])
    for s in specs:
        s["rows"] = int(s["rows"])
        s["gravity"] = [float(x) for x in str(s["gravity"]).split(",")]
        if len(s["gravity"]) != 3:
            sys.exit("--gravity needs x,y,z")
        if not s["name"]:
            s["name"] = os.path.splitext(os.path.basename(s["model"]))[0] + ("_floating" if s["floating"] else "")
        if s["seed"] is None:  # stable across runs and machines (not Python's salted hash())
            s["seed"] = zlib.crc32(s["name"].encode())
        s["seed"] = int(s["seed"])
    return out, specs


# ----------------------------------------------------------------------------- model and names
def load(spec):
    path = spec["model"] if os.path.isabs(spec["model"]) else os.path.join(ROOT, spec["model"])
    if not os.path.exists(path):
        path = spec["model"]
    if spec["floating"]:
        model = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
    else:
        model = pin.buildModelFromUrdf(path)
    model.gravity = pin.Motion(np.array(spec["gravity"]), np.zeros(3))
    return model, path


def joint_components(j):
    """(q component names, v component names) of one joint; [None] for a 1-DoF joint (pin_ref.py)."""
    s = j.shortname()
    if s == "JointModelFreeFlyer":
        return ["x", "y", "z", "qx", "qy", "qz", "qw"], ["vx", "vy", "vz", "wx", "wy", "wz"]
    if s == "JointModelSpherical":
        return ["qx", "qy", "qz", "qw"], ["wx", "wy", "wz"]
    if s == "JointModelSphericalZYX":
        return ["rz", "ry", "rx"], ["rz", "ry", "rx"]
    if s == "JointModelPlanar":
        return ["x", "y", "cos", "sin"], ["vx", "vy", "wz"]
    if s == "JointModelTranslation":
        return ["x", "y", "z"], ["x", "y", "z"]
    if s.startswith("JointModelRUB") or s == "JointModelRevoluteUnboundedUnaligned":
        return ["cos", "sin"], [None]
    if j.nq == 1 and j.nv == 1:
        return [None], [None]
    return [str(k) for k in range(j.nq)], [str(k) for k in range(j.nv)]


def dof_names(model):
    qn, vn = [], []
    for i in range(1, model.njoints):
        name = model.names[i]
        qc, vc = joint_components(model.joints[i])
        qn += [name if c is None else f"{name}:{c}" for c in qc]
        vn += [name if c is None else f"{name}:{c}" for c in vc]
    assert len(qn) == model.nq and len(vn) == model.nv
    return qn, vn


def joint_kind(j):
    s = j.shortname()
    if s.startswith("JointModelR") and "UB" not in s and "Unbounded" not in s and j.nq == 1:
        return "revolute"
    if s.startswith("JointModelP") and j.nq == 1:
        return "prismatic"
    return {"JointModelFreeFlyer": "free", "JointModelSpherical": "spherical",
            "JointModelRUBX": "continuous", "JointModelRUBY": "continuous", "JointModelRUBZ": "continuous",
            "JointModelRevoluteUnboundedUnaligned": "continuous"}.get(s, s)


# ----------------------------------------------------------------------------- states
def random_q(model, rng, neutral=False):
    q = pin.neutral(model).copy()
    for i in range(1, model.njoints):
        j = model.joints[i]
        iq, kind = j.idx_q, joint_kind(j)
        lo, hi = model.lowerPositionLimit[iq:iq + j.nq], model.upperPositionLimit[iq:iq + j.nq]
        if kind in ("revolute", "prismatic"):
            l, h = float(lo[0]), float(hi[0])
            if not (np.isfinite(l) and np.isfinite(h) and l < h):
                l, h = (-np.pi, np.pi) if kind == "revolute" else (-1.0, 1.0)
            mid, half = 0.5 * (l + h), 0.5 * (h - l) * 0.95
            if neutral:
                q[iq] = min(max(0.0, mid - half), mid + half)
            else:
                q[iq] = rng.uniform(mid - half, mid + half)
        elif neutral:
            continue
        elif kind == "continuous":
            t = rng.uniform(-np.pi, np.pi)
            q[iq:iq + 2] = [np.cos(t), np.sin(t)]
        elif kind in ("free", "spherical"):
            quat = rng.normal(size=4)
            quat /= np.linalg.norm(quat)
            if quat[3] < 0:
                quat = -quat
            if kind == "free":
                q[iq:iq + 3] = rng.uniform(-0.5, 0.5, 3)
                q[iq + 3:iq + 7] = quat
            else:
                q[iq:iq + 4] = quat
        else:
            sys.exit(f"joint {model.names[i]} of type {j.shortname()}: no sampler")
    return q


def make_states(model, data, rows, seed):
    rng = np.random.default_rng(seed)
    Q, V, A, T = [], [], [], []
    for r in range(rows):
        q = random_q(model, rng, neutral=(r == 0))
        if r <= 1:
            v, a = np.zeros(model.nv), np.zeros(model.nv)
        else:
            v, a = rng.normal(0.0, 1.0, model.nv), rng.normal(0.0, 2.0, model.nv)
        g = pin.computeGeneralizedGravity(model, data, q).copy()
        dM = np.diag(pin.crba(model, data, q)).copy()
        tau = np.zeros(model.nv) if r == 0 else g + dM * rng.normal(0.0, 1.0, model.nv)
        Q.append(q), V.append(v), A.append(a), T.append(tau)
    return [np.array(x) for x in (Q, V, A, T)]


# ----------------------------------------------------------------------------- output
def write_csv(path, header, rows):
    with open(path, "w", newline="\n") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join("%.17g" % (0.0 if x == 0 else x) for x in r) + "\n")


def symmetric_M(model, data, q):
    M = pin.crba(model, data, q).copy()
    return np.triu(M) + np.triu(M, 1).T


def self_check(model, data, q, v, a, tau, name, r):
    """Pinocchio against itself; a fixture is only written when these hold."""
    M = symmetric_M(model, data, q)
    nle = pin.nonLinearEffects(model, data, q, v).copy()
    tau_id = pin.rnea(model, data, q, v, a).copy()
    scale = 1.0 + np.abs(tau_id).max() + np.abs(M).max()
    err = {
        "rnea = M a + nle": np.abs(M @ a + nle - tau_id).max(),
        "aba(rnea(a)) = a": np.abs(pin.aba(model, data, q, v, tau_id) - a).max() * np.abs(M).max(),
        "M a_aba + nle = tau": np.abs(M @ pin.aba(model, data, q, v, tau) + nle - tau).max(),
        "nle(v=0) = g": np.abs(pin.nonLinearEffects(model, data, q, 0 * v) -
                               pin.computeGeneralizedGravity(model, data, q)).max(),
    }
    bad = {k: e for k, e in err.items() if not e <= 1e-9 * scale}
    if bad or np.linalg.eigvalsh(M).min() <= 0:
        sys.exit(f"{name} row {r}: Pinocchio self-check failed: {bad}, min eig M {np.linalg.eigvalsh(M).min()}")
    return max(err.values()) / scale


def run(spec, out):
    model, path = load(spec)
    data = model.createData()
    name = spec["name"]
    qn, vn = dof_names(model)
    Q, V, A, T = make_states(model, data, spec["rows"], spec["seed"])
    d = os.path.join(out, name)
    os.makedirs(d, exist_ok=True)

    write_csv(os.path.join(d, "states.csv"),
              [f"q:{n}" for n in qn] + [f"v:{n}" for n in vn] + [f"a:{n}" for n in vn] + [f"tau:{n}" for n in vn],
              [np.concatenate(x) for x in zip(Q, V, A, T)])

    joint_frames = [k for k, f in enumerate(model.frames) if f.type == pin.FrameType.JOINT]
    body_frames = [k for k, f in enumerate(model.frames) if f.type == pin.FrameType.BODY]
    fk_header = []
    for k in joint_frames:
        fk_header += [f"{model.frames[k].name}:{c}" for c in "xyz"]
    for k in body_frames:
        fk_header += [f"{model.frames[k].name}:{c}" for c in "xyz"]
        fk_header += [f"{model.frames[k].name}:r{i}{j}" for i in range(3) for j in range(3)]

    res = {k: [] for k in ("rnea", "crba", "aba", "gravity", "nle", "fk", "energy")}
    worst = 0.0
    for r, (q, v, a, tau) in enumerate(zip(Q, V, A, T)):
        worst = max(worst, self_check(model, data, q, v, a, tau, name, r))
        res["rnea"].append(pin.rnea(model, data, q, v, a).copy())
        res["crba"].append(symmetric_M(model, data, q).reshape(-1))
        res["aba"].append(pin.aba(model, data, q, v, tau).copy())
        res["gravity"].append(pin.computeGeneralizedGravity(model, data, q).copy())
        res["nle"].append(pin.nonLinearEffects(model, data, q, v).copy())
        pin.framesForwardKinematics(model, data, q)
        row = []
        for k in joint_frames:
            row += list(data.oMf[k].translation)
        for k in body_frames:
            row += list(data.oMf[k].translation) + list(data.oMf[k].rotation.reshape(-1))
        res["fk"].append(row)
        ke = pin.computeKineticEnergy(model, data, q, v)
        pe = pin.computePotentialEnergy(model, data, q)
        res["energy"].append([ke, pe, ke + pe] + list(pin.centerOfMass(model, data, q)))

    headers = {
        "rnea": [f"tau:{n}" for n in vn],
        "crba": [f"M:{i}:{j}" for i in range(model.nv) for j in range(model.nv)],
        "aba": [f"a:{n}" for n in vn],
        "gravity": [f"g:{n}" for n in vn],
        "nle": [f"nle:{n}" for n in vn],
        "fk": fk_header,
        "energy": ["kinetic", "potential", "total", "com:x", "com:y", "com:z"],
    }
    for k, rows in res.items():
        write_csv(os.path.join(d, f"{k}.csv"), headers[k], rows)

    joints = []
    for i in range(1, model.njoints):
        j = model.joints[i]
        joints.append({"name": model.names[i], "type": joint_kind(j), "pinocchio_type": j.shortname(),
                       "nq": j.nq, "nv": j.nv, "idx_q": j.idx_q, "idx_v": j.idx_v,
                       "parent": model.names[model.parents[i]]})
    rel = os.path.relpath(os.path.abspath(path), ROOT)
    meta = {
        "name": name,
        "source": rel if not rel.startswith("..") else os.path.basename(path),
        "floating": bool(spec["floating"]),
        "gravity": spec["gravity"],
        "nq": model.nq, "nv": model.nv, "rows": spec["rows"], "seed": spec["seed"],
        "total_mass": pin.computeTotalMass(model),
        "joints": joints,
        "q_names": qn, "v_names": vn,
        "fk_joint_frames": [model.frames[k].name for k in joint_frames],
        "fk_body_frames": [model.frames[k].name for k in body_frames],
        "generator": "tools/pinocchio_fixtures.py",
        "pinocchio": pin.__version__, "numpy": np.__version__,
        "notes": "Pinocchio joint order (depth-first, children in the order urdfdom lists them); "
                 "M:<i>:<j> and every <dof> column use v_names order. Fixed joints are merged into "
                 "their parent body. A fixed-base model's root link inertia is not counted in "
                 "total_mass (it is welded to the world).",
    }
    with open(os.path.join(d, "model.json"), "w", newline="\n") as f:
        json.dump(meta, f, indent=1)
        f.write("\n")
    print(f"{name}: nq={model.nq} nv={model.nv} rows={spec['rows']} seed={spec['seed']} "
          f"gravity={spec['gravity']} -> {os.path.relpath(d, os.getcwd())} "
          f"(self-check worst relative error {worst:.1e})")


def main(argv=None):
    out, specs = parse_args(sys.argv[1:] if argv is None else argv)
    for s in specs:
        run(s, out)


if __name__ == "__main__":
    main()
