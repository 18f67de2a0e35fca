#!/usr/bin/env python3
"""DH-table robots and their golden fixtures from Peter Corke's Robotics Toolbox for Python.

Run with the toolbox venv; Pinocchio's venv is used for the cross-check (see tools/README.md):

    python3 -m venv ~/.cache/rtb && ~/.cache/rtb/bin/pip install roboticstoolbox-python==1.5.0
    ~/.cache/rtb/bin/python tools/rtb_fixtures.py [--pin-python ~/.cache/pin-oracle/bin/python]
                                                  [--no-crosscheck] [--keep-urdf DIR]

Robots (all rigid-body only: motor inertia Jm = 0, gear ratio G = 1, viscous B = 0 and Coulomb
Tc = 0, so `rne` is pure Newton-Euler):
  puma560      rtb.models.DH.Puma560(), standard DH (Corke's parameters, base height in d1)
  puma560_mdh  the same physical arm in modified DH (Craig), derived here from the standard
               table: alpha, a of MDH link i are alpha, a of standard link i-1; d, theta, offset
               unchanged; COM and inertia re-expressed in the MDH frame (r' = [a,0,0] + Rx(alpha) r,
               I' = Rx(alpha) I Rx(alpha)^T); tool = Tx(a6) Rx(alpha6) (= identity for the Puma).
               The toolbox has no MDH Puma of its own; its rne must equal puma560's (checked).
  stanford     rtb.models.DH.Stanford(), standard DH, joint 3 prismatic. Parameters verbatim from
               the toolbox, including its odd COM offsets (e.g. link 3 r = [0, 0, -6.447] m).

Writes data/<name>.toml (our DH table format, documented at the top of each file) and
tests/fixtures/rtb/<name>/:
  states.csv   q:j1..q:jN, v:j1..v:jN, a:j1..a:jN              (8 rows; see meta.json "rows")
  rnea.csv     tau:j1..tau:jN     robot.rne(q, v, a)            (gravity included)
  gravity.csv  g:j1..g:jN         robot.gravload(q)
  crba.csv     M:<i>:<j>          robot.inertia(q), full symmetric, row-major, 0-based
  fk.csv       x,y,z,r00..r22     robot.fkine(q) (end effector incl. tool; r<i><j> row i col j)
               then j<i>:x,y,z    position of link frame i (i = 1..N) from robot.fkine_all(q)
  meta.json    joint names, types, row labels, gravity, versions

Gravity: the toolbox's `robot.gravity` is the gravitational acceleration vector in the world
frame, [0, 0, -9.81] (pointing down; rne starts the recursion with base acceleration -gravity).
That is articula's convention too (`gravity = [0, 0, -9.81]`); the script proves it by checking
gravload against the gradient of the potential energy -sum m_i g . c_i(q).

Checks (the script stops if one fails): rne (C) == rne_python; gravload == rne(q, 0, 0) ==
dV/dq (finite differences); puma560_mdh == puma560 for rne, gravload, inertia and end-effector
pose; and, with Pinocchio, a URDF written from each DH table (tmp dir, or --keep-urdf) gives the
same rnea, gravity, mass matrix and link-frame positions (to 1e-9).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import roboticstoolbox as rtb
from spatialmath import SE3

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))
TOL = 1e-9


# ----------------------------------------------------------------------------- robots
def rigid(robot):
    """Motor inertia, gearing and friction off: rne becomes pure rigid-body dynamics."""
    for L in robot.links:
        L.Jm, L.G, L.B, L.Tc = 0.0, 1.0, 0.0, np.zeros(2)
        assert not L.isflip
    robot.dynchanged()
    return robot


def clean(x, eps=1e-15):
    """Drop the 1e-17 residue that cos(pi/2) leaves, so the tables read as they are meant."""
    x = np.array(x, dtype=float)
    x[np.abs(x) < eps] = 0.0
    return x + 0.0


def rotx(t):
    c, s = math.cos(t), math.sin(t)
    if abs(c) < 1e-15:
        c = 0.0
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def to_mdh(std):
    """The same arm as `std` (standard DH) written in modified DH (Craig)."""
    links, prev_a, prev_alpha = [], 0.0, 0.0
    for L in std.links:
        R = rotx(L.alpha)
        r = clean(np.array([L.a, 0.0, 0.0]) + R @ L.r)
        I = clean(R @ L.I @ R.T)
        I = 0.5 * (I + I.T)
        kw = dict(a=prev_a, alpha=prev_alpha, offset=L.offset, qlim=L.qlim, m=L.m, r=r, I=I,
                  Jm=0.0, G=1.0, B=0.0, Tc=[0.0, 0.0])
        links.append(rtb.PrismaticMDH(theta=L.theta, **kw) if L.isprismatic else rtb.RevoluteMDH(d=L.d, **kw))
        prev_a, prev_alpha = L.a, L.alpha
    tool = std.tool * SE3(prev_a, 0, 0) * SE3.Rx(prev_alpha)
    mdh = rtb.DHRobot(links, name=std.name + " (MDH)", tool=tool, base=std.base, gravity=std.gravity)
    return rigid(mdh)


def robots():
    puma = rigid(rtb.models.DH.Puma560())
    stanford = rigid(rtb.models.DH.Stanford())
    for r in (puma, stanford):
        assert np.allclose(r.base.A, np.eye(4)) and np.allclose(r.tool.A, np.eye(4)), r.name
    return [("puma560", puma, "standard"), ("puma560_mdh", to_mdh(puma), "modified"),
            ("stanford", stanford, "standard")]


# ----------------------------------------------------------------------------- states
def states(name, robot, rng):
    n = robot.n
    lo, hi = robot.qlim[0], robot.qlim[1]
    mid, half = 0.5 * (lo + hi), 0.45 * (hi - lo)

    def rnd():
        return mid + half * rng.uniform(-1, 1, n)

    def va():
        return rng.normal(0, 1, n), rng.normal(0, 2, n)

    z = np.zeros(n)
    rows = [("qz", robot.qz, z, z)]
    if name.startswith("puma"):
        rows += [("qr", robot.configs["qr"], z, z), ("qn", robot.configs["qn"], *va()),
                 ("qs", robot.configs["qs"], *va())]
    else:
        rows += [("qz+v,a", robot.qz, *va()), ("random at rest", rnd(), z, z)]
    while len(rows) < 8:
        rows.append(("random", rnd(), *va()))
    return rows


# ----------------------------------------------------------------------------- our DH TOML
def f(x):
    return repr(float(x) + 0.0)


def toml(name, robot, convention, path):
    frame = ("link frame i = the DH frame at the DISTAL end of link i (standard DH, Corke's "
             "robot.links[i])" if convention == "standard" else
             "link frame i = the modified-DH frame of link i, on joint axis i (Craig)")
    out = [
        "# articula DH table. Angles in radians, lengths in metres, SI throughout.",
        "# Generated by tools/rtb_fixtures.py from Peter Corke's Robotics Toolbox for Python "
        f"{rtb.__version__} ({'rtb.models.DH.Puma560' if name.startswith('puma') else 'rtb.models.DH.Stanford'}"
        f"{', converted to modified DH' if convention == 'modified' else ''}); do not edit by hand.",
        "#",
        "# Top level:",
        "#   name        robot name",
        "#   convention  \"standard\" (Denavit-Hartenberg: A_i = Rz(theta) Tz(d) Tx(a) Rx(alpha)) or",
        "#               \"modified\" (Craig: A_i = Rx(alpha) Tx(a) Rz(theta) Tz(d); alpha, a are those",
        "#               of the link BEFORE the joint, as in the toolbox's RevoluteMDH)",
        "#   gravity     gravitational acceleration in the world (= base) frame, m/s^2 (down is -z)",
        "# One [[link]] per joint, base to tip:",
        "#   type    \"R\" revolute (theta is the joint variable) or \"P\" prismatic (d is)",
        "#   theta   rad (ignored for R: the joint variable)",
        "#   d       m   (ignored for P: the joint variable)",
        "#   a       m",
        "#   alpha   rad",
        "#   offset  added to q before use (Corke's offset): theta = q + offset (R), d = q + offset (P)",
        "#   qlim    [lower, upper] of q, rad or m",
        "#   m       kg",
        "#   r       centre of mass in the link frame, m",
        "#   I       inertia about the centre of mass, link-frame axes, kg m^2, as",
        "#           [Ixx, Iyy, Izz, Ixy, Iyz, Ixz] (Corke's order); a 3x3 [[..],[..],[..]] is also accepted",
        f"#   {frame}.",
        "# Motor inertia, gearing and friction are not part of this table (rigid-body dynamics only).",
        "# Base and tool transforms are the identity (the base height is in d1).",
        "",
        f'name = "{name}"',
        f'convention = "{convention}"',
        f"gravity = [{', '.join(f(x) for x in robot.gravity)}]",
    ]
    for L in robot.links:
        I = L.I
        out += [
            "",
            "[[link]]",
            f'type = "{"P" if L.isprismatic else "R"}"',
            f"theta = {f(L.theta if L.isprismatic else 0.0)}",
            f"d = {f(0.0 if L.isprismatic else L.d)}",
            f"a = {f(L.a)}",
            f"alpha = {f(L.alpha)}",
            f"offset = {f(L.offset)}",
            f"qlim = [{f(L.qlim[0])}, {f(L.qlim[1])}]",
            f"m = {f(L.m)}",
            f"r = [{', '.join(f(x) for x in L.r)}]",
            f"I = [{', '.join(f(x) for x in (I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[1, 2], I[0, 2]))}]",
        ]
    with open(path, "w", newline="\n") as fh:
        fh.write("\n".join(out) + "\n")


def read_toml_back(path):
    """Parse what we wrote (tomllib) and rebuild the DH robot from it: the TOML alone suffices."""
    import tomllib
    with open(path, "rb") as fh:
        t = tomllib.load(fh)
    links = []
    for L in t["link"]:
        Ixx, Iyy, Izz, Ixy, Iyz, Ixz = L["I"]
        I = np.array([[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]])
        kw = dict(a=L["a"], alpha=L["alpha"], offset=L["offset"], qlim=L["qlim"], m=L["m"], r=L["r"], I=I,
                  Jm=0.0, G=1.0, B=0.0, Tc=[0.0, 0.0])
        mdh = t["convention"] == "modified"
        if L["type"] == "P":
            links.append((rtb.PrismaticMDH if mdh else rtb.PrismaticDH)(theta=L["theta"], **kw))
        else:
            links.append((rtb.RevoluteMDH if mdh else rtb.RevoluteDH)(d=L["d"], **kw))
    return rtb.DHRobot(links, name=t["name"], gravity=t["gravity"])


# ----------------------------------------------------------------------------- URDF for the cross-check
def rpy(R):
    p = math.asin(max(-1.0, min(1.0, -R[2, 0])))
    return math.atan2(R[2, 1], R[2, 2]), p, math.atan2(R[1, 0], R[0, 0])


def origin(T):
    T = np.asarray(T)
    return (f'<origin xyz="{" ".join(repr(float(x)) for x in T[:3, 3])}" '
            f'rpy="{" ".join(repr(float(x)) for x in rpy(T[:3, :3]))}"/>')


def inertial(L, T):
    """<inertial> for link L whose COM frame is T (4x4) in the URDF link frame."""
    c = T[:3, :3] @ L.r + T[:3, 3]
    Tc = np.eye(4)
    Tc[:3, :3], Tc[:3, 3] = T[:3, :3], c
    I = L.I
    return (f'    <inertial>{origin(Tc)}<mass value="{float(L.m)!r}"/>'
            f'<inertia ixx="{float(I[0, 0])!r}" ixy="{float(I[0, 1])!r}" ixz="{float(I[0, 2])!r}" '
            f'iyy="{float(I[1, 1])!r}" iyz="{float(I[1, 2])!r}" izz="{float(I[2, 2])!r}"/></inertial>')


def dh_urdf(name, robot):
    """URDF of a DH robot. URDF link i's frame is the frame right after joint i's motion:
    standard: F_{i-1} Rz(theta_i) [Tz(d_i) if P], so the DH frame F_i = that * X_i with
    X_i = [Tz(d_i) if R] Tx(a_i) Rx(alpha_i); modified: the MDH frame itself. The DH frame of
    every link is added as a massless child `frame<i>` on a fixed joint, the tool as `tool`."""
    def Tz(x): return SE3.Tz(x).A
    def Tx(x): return SE3.Tx(x).A
    def Rz(t): return SE3.Rz(t).A
    def Rx(t): return SE3.Rx(t).A
    parts = [f'<?xml version="1.0"?>\n<robot name="{name}">', '  <link name="base"/>']
    prev, Xprev = "base", robot.base.A
    for i, L in enumerate(robot.links, start=1):
        kind = "prismatic" if L.isprismatic else "revolute"
        if robot.mdh:
            pre = Rx(L.alpha) @ Tx(L.a)
            J = pre @ (Rz(L.theta) @ Tz(L.offset) if L.isprismatic else Rz(L.offset) @ Tz(L.d))
            X = np.eye(4)
        else:
            J = Xprev @ (Rz(L.theta) @ Tz(L.offset) if L.isprismatic else Rz(L.offset))
            X = (np.eye(4) if L.isprismatic else Tz(L.d)) @ Tx(L.a) @ Rx(L.alpha)
        parts += [f'  <link name="link{i}">', inertial(L, X), '  </link>',
                  f'  <joint name="j{i}" type="{kind}"><parent link="{prev}"/><child link="link{i}"/>'
                  f'{origin(J)}<axis xyz="0 0 1"/><limit lower="-10" upper="10" effort="1" velocity="1"/></joint>',
                  f'  <link name="frame{i}"/>',
                  f'  <joint name="frame{i}_fixed" type="fixed"><parent link="link{i}"/><child link="frame{i}"/>'
                  f'{origin(X)}</joint>']
        prev, Xprev = f"link{i}", X
    parts += ['  <link name="tool"/>',
              f'  <joint name="tool_fixed" type="fixed"><parent link="frame{robot.n}"/><child link="tool"/>'
              f'{origin(robot.tool.A)}</joint>', '</robot>\n']
    return "\n".join(parts)


PIN_SCRIPT = r"""
import json, sys
import numpy as np, pinocchio as pin
job = json.load(sys.stdin)
model = pin.buildModelFromUrdf(job["urdf"])
model.gravity = pin.Motion(np.array(job["gravity"]), np.zeros(3))
data = model.createData()
names = [model.names[i] for i in range(1, model.njoints)]
assert names == ["j%d" % (i + 1) for i in range(model.nv)], names
fr = [model.getFrameId(n) for n in job["frames"]]
out = {"pinocchio": pin.__version__, "rnea": [], "gravity": [], "M": [], "frames": [], "tool_R": []}
for q, v, a in zip(job["q"], job["v"], job["a"]):
    q, v, a = np.array(q), np.array(v), np.array(a)
    out["rnea"].append(pin.rnea(model, data, q, v, a).tolist())
    out["gravity"].append(pin.computeGeneralizedGravity(model, data, q).tolist())
    M = pin.crba(model, data, q); M = np.triu(M) + np.triu(M, 1).T
    out["M"].append(M.tolist())
    pin.framesForwardKinematics(model, data, q)
    out["frames"].append([data.oMf[k].translation.tolist() for k in fr])
    out["tool_R"].append(data.oMf[fr[-1]].rotation.tolist())
json.dump(out, sys.stdout)
"""


def pinocchio_check(name, robot, rows, res, pin_python, keep):
    text = dh_urdf(name, robot)
    d = keep or tempfile.mkdtemp(prefix="rtb_xcheck_")
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, f"{name}_dh.urdf")
    with open(path, "w") as fh:
        fh.write(text)
    job = {"urdf": path, "gravity": list(map(float, robot.gravity)),
           "frames": [f"frame{i}" for i in range(1, robot.n + 1)] + ["tool"],
           "q": [r[1].tolist() for r in rows], "v": [r[2].tolist() for r in rows],
           "a": [r[3].tolist() for r in rows]}
    p = subprocess.run([pin_python, "-c", PIN_SCRIPT], input=json.dumps(job), capture_output=True,
                       text=True, check=False)
    if p.returncode != 0:
        sys.exit(f"Pinocchio cross-check failed to run ({pin_python}):\n{p.stderr}")
    P = json.loads(p.stdout)
    err = {
        "rnea": np.abs(np.array(P["rnea"]) - res["rnea"]).max(),
        "gravity": np.abs(np.array(P["gravity"]) - res["gravity"]).max(),
        "M": np.abs(np.array(P["M"]) - res["M"]).max(),
        "link frames": np.abs(np.array(P["frames"])[:, :-1, :] - res["frames"]).max(),
        "tool pose": max(np.abs(np.array(P["frames"])[:, -1, :] - res["ee"][:, :3, 3]).max(),
                         np.abs(np.array(P["tool_R"]) - res["ee"][:, :3, :3]).max()),
    }
    if not keep:
        os.remove(path)
        os.rmdir(d)
    return P["pinocchio"], err


# ----------------------------------------------------------------------------- fixtures
def compute(robot, rows):
    Q = np.array([r[1] for r in rows], dtype=float)
    V = np.array([r[2] for r in rows], dtype=float)
    A = np.array([r[3] for r in rows], dtype=float)
    res = {"rnea": [], "rnea_py": [], "gravity": [], "M": [], "ee": [], "frames": []}
    for q, v, a in zip(Q, V, A):
        res["rnea"].append(np.asarray(robot.rne(q, v, a), dtype=float).reshape(-1))
        res["rnea_py"].append(np.asarray(robot.rne_python(q, v, a), dtype=float).reshape(-1))
        res["gravity"].append(np.asarray(robot.gravload(q), dtype=float).reshape(-1))
        res["M"].append(np.asarray(robot.inertia(q), dtype=float))
        res["ee"].append(robot.fkine(q).A)
        T = robot.fkine_all(q)
        assert len(T) == robot.n + 1 and np.allclose(T[0].A, robot.base.A)
        res["frames"].append([T[i].t for i in range(1, robot.n + 1)])
    return Q, V, A, {k: np.array(v) for k, v in res.items()}


def potential_gradient(robot, q, h=1e-6):
    """dV/dq with V(q) = -sum_i m_i gravity . c_i(q), c_i the COM of link i in the world."""
    def V(q):
        T = robot.fkine_all(q)
        return -sum(L.m * np.dot(robot.gravity, T[i + 1].A[:3, :3] @ L.r + T[i + 1].t)
                    for i, L in enumerate(robot.links))
    g = np.zeros(robot.n)
    for j in range(robot.n):
        e = np.zeros(robot.n)
        e[j] = h
        g[j] = (V(q + e) - V(q - e)) / (2 * h)
    return g


def write_csv(path, header, rows):
    with open(path, "w", newline="\n") as fh:
        fh.write(",".join(header) + "\n")
        for r in rows:
            fh.write(",".join("%.17g" % (float(x) + 0.0) for x in r) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pin-python", default=os.path.expanduser("~/.cache/pin-oracle/bin/python"),
                    help="python with pinocchio for the cross-check (default ~/.cache/pin-oracle/bin/python)")
    ap.add_argument("--no-crosscheck", action="store_true", help="skip the Pinocchio cross-check")
    ap.add_argument("--keep-urdf", metavar="DIR", help="keep the cross-check URDFs in DIR (not committed)")
    ap.add_argument("--seed", type=int, default=560)
    args = ap.parse_args()

    all_res = {}
    for k, (name, robot, convention) in enumerate(robots()):
        rng = np.random.default_rng(args.seed + k)
        rows = states(name, robot, rng) if name != "puma560_mdh" else all_res["puma560"][0]
        Q, V, A, res = compute(robot, rows)
        all_res[name] = (rows, res)
        n = robot.n
        jn = [f"j{i}" for i in range(1, n + 1)]

        # --- self-checks of the toolbox
        checks = {
            "rne (C) vs rne_python": np.abs(res["rnea"] - res["rnea_py"]).max(),
            "gravload vs rne(q,0,0)": max(np.abs(res["gravity"][i] - np.asarray(robot.rne(Q[i], 0 * Q[i], 0 * Q[i])).reshape(-1)).max()
                                          for i in range(len(Q))),
            "rne vs M a + nle": max(np.abs(res["M"][i] @ A[i] + np.asarray(robot.rne(Q[i], V[i], 0 * Q[i])).reshape(-1)
                                           - res["rnea"][i]).max() for i in range(len(Q))),
        }
        dv = max(np.abs(potential_gradient(robot, Q[i]) - res["gravity"][i]).max() for i in range(len(Q)))
        checks["gravload vs dV/dq (finite diff., tol 1e-5)"] = dv
        if name == "puma560_mdh":
            ref = all_res["puma560"][1]
            checks["mdh vs standard: rne"] = np.abs(res["rnea"] - ref["rnea"]).max()
            checks["mdh vs standard: gravload"] = np.abs(res["gravity"] - ref["gravity"]).max()
            checks["mdh vs standard: inertia"] = np.abs(res["M"] - ref["M"]).max()
            checks["mdh vs standard: fkine"] = np.abs(res["ee"] - ref["ee"]).max()

        # --- our TOML, and the robot rebuilt from it alone
        tpath = os.path.join(ROOT, "data", f"{name}.toml")
        toml(name, robot, convention, tpath)
        back = read_toml_back(tpath)
        checks["robot rebuilt from the TOML: rne"] = max(
            np.abs(np.asarray(back.rne(Q[i], V[i], A[i])).reshape(-1) - res["rnea"][i]).max() for i in range(len(Q)))
        checks["robot rebuilt from the TOML: fkine"] = max(
            np.abs(back.fkine(Q[i]).A - res["ee"][i]).max() for i in range(len(Q)))

        pin_version = None
        if not args.no_crosscheck:
            pin_version, perr = pinocchio_check(name, robot, rows, res, args.pin_python, args.keep_urdf)
            checks.update({f"pinocchio (DH->URDF) vs rtb: {k}": v for k, v in perr.items()})
        print(f"{name} ({convention} DH, n={n}):")
        for k, v in checks.items():
            tol = 1e-5 if "finite diff" in k else TOL
            print(f"  {'ok ' if v <= tol else 'BAD'} {k}: max abs diff {v:.2e}")
        bad = [k for k, v in checks.items() if not v <= (1e-5 if "finite diff" in k else TOL)]
        if bad:
            sys.exit(f"{name}: checks failed: {bad}")

        # --- fixtures
        d = os.path.join(ROOT, "tests", "fixtures", "rtb", name)
        os.makedirs(d, exist_ok=True)
        write_csv(os.path.join(d, "states.csv"),
                  [f"q:{j}" for j in jn] + [f"v:{j}" for j in jn] + [f"a:{j}" for j in jn],
                  [np.concatenate(x) for x in zip(Q, V, A)])
        write_csv(os.path.join(d, "rnea.csv"), [f"tau:{j}" for j in jn], res["rnea"])
        write_csv(os.path.join(d, "gravity.csv"), [f"g:{j}" for j in jn], res["gravity"])
        write_csv(os.path.join(d, "crba.csv"), [f"M:{i}:{j}" for i in range(n) for j in range(n)],
                  [M.reshape(-1) for M in res["M"]])
        fk_header = ["x", "y", "z"] + [f"r{i}{j}" for i in range(3) for j in range(3)]
        fk_header += [f"{j}:{c}" for j in jn for c in "xyz"]
        write_csv(os.path.join(d, "fk.csv"), fk_header,
                  [list(T[:3, 3]) + list(T[:3, :3].reshape(-1)) + list(F.reshape(-1))
                   for T, F in zip(res["ee"], res["frames"])])
        meta = {
            "name": name, "convention": convention, "n": n, "joints": jn,
            "joint_types": ["P" if L.isprismatic else "R" for L in robot.links],
            "dh_table": f"data/{name}.toml",
            "gravity": [float(x) for x in robot.gravity],
            "gravity_note": "gravitational acceleration in the world frame (down = -z); rne starts "
                            "from base acceleration -gravity; rnea includes gravity, gravity.csv is "
                            "gravload = rne(q, 0, 0)",
            "rigid_body_only": "Jm = 0, G = 1, B = 0, Tc = 0 on every link",
            "rows": [r[0] for r in rows],
            "fk": "x,y,z,r00..r22: fkine(q) (base * links * tool); j<i>:x,y,z: origin of DH link frame i "
                  "(fkine_all(q)[i]), world frame",
            "generator": "tools/rtb_fixtures.py", "seed": args.seed,
            "roboticstoolbox": rtb.__version__, "numpy": np.__version__,
            "crosscheck": {"pinocchio": pin_version,
                           "max_abs_diff": {k: float(v) for k, v in checks.items()}},
        }
        with open(os.path.join(d, "meta.json"), "w", newline="\n") as fh:
            json.dump(meta, fh, indent=1)
            fh.write("\n")


if __name__ == "__main__":
    main()
