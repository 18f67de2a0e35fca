#!/usr/bin/env python3
"""MuJoCo reproduces articula's inverse dynamics on an exported MJCF.

For a take, this runs `articula export mjcf`, `articula export states` and
`articula id --contact none` with the same take options, loads the MJCF with the `mujoco`
wheel (contacts disabled: `mjDSBL_CONTACT`), sets each frame's q, v, a in MuJoCo's coordinates
and compares `mj_inverse`'s `qfrc_inverse` with articula's torques, coordinate by coordinate,
in articula's coordinates. It prints the largest difference relative to the frame's largest
torque (and absolute), and exits non-zero above --tol (default 1e-8).

Coordinate conversions (MuJoCo's conventions, https://mujoco.readthedocs.io):
- hinge / slide: the same number (joint named as articula's coordinate);
- ball: quaternion w first (articula: x, y, z, w); qvel, qacc and torque are the angular
  velocity, acceleration and moment in the child frame, as articula's;
- free root, from the file's `<custom><text name="articula:ROOT">` map:
  * articula's free joint (ball model; v linear in the child frame, spatial acceleration):
    qpos = (p0 + R0 x, q0 * q), qvel = (R v, w), qacc = (R (a + w x v), dw), where R is the
    body's rotation in the world; forces: f = R^T qfrc[0:3], n = qfrc[3:6];
  * the euler model's 3 slides + 3 hinges: position p0 + R0 sum(x_k e_k), rotation
    R0 R1 R2 R3; linear rates R0 sum(xdot_k e_k); angular velocity and acceleration in the body
    by the recursion w = R_k^T w + a_k qd_k, dw = R_k^T dw + a_k qdd_k + w x a_k qd_k; forces
    slide_k = (R0 e_k) . qfrc[0:3], hinge_k = S_k . qfrc[3:6] with S_k = (R_k+1 .. R_3)^T a_k.

With `--format urdf` the same is done on `articula export urdf` (the euler model: its root is
articula's own slides and hinges, every coordinate maps 1:1; MuJoCo gives the massless links
1e-9 kg, the file's `boundmass`), which also checks that MuJoCo's URDF import reads the
gravity of the file's `<mujoco><option gravity>` (it is printed, and enters every torque).

Usage: check_mujoco.py TAKE.bvh [--articula BIN] [--tol 1e-8] [--keep DIR] [--format urdf]
-- [take options] (e.g. `-- --joints ball`). Needs `pip install mujoco numpy`.
"""

import argparse
import csv
import os
import subprocess
import sys
import tempfile

import mujoco
import numpy as np


def read_csv(path):
    with open(path, newline="") as f:
        r = csv.reader(f)
        header = next(r)
        rows = np.array([[float(x) for x in row] for row in r])
    return {h: rows[:, k] for k, h in enumerate(header)}, len(rows)


def rot(axis, angle):
    axis = np.asarray(axis, float)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def quat_to_mat(q_wxyz):
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, np.asarray(q_wxyz, float))
    return m.reshape(3, 3)


def mat_to_quat(m):
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(m).reshape(9))
    return q


def root_maps(model):
    """{free joint name: [(coordinate, kind, axis)]} from the custom text elements."""
    maps = {}
    for t in range(model.ntext):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_TEXT, t)
        if not name.startswith("articula:"):
            continue
        adr, size = model.text_adr[t], model.text_size[t]
        data = bytes(model.text_data[adr:adr + size]).split(b"\0")[0].decode()
        entries = []
        for e in data.split(";"):
            parts = e.split()
            axis = np.array([float(x) for x in parts[2:5]]) if len(parts) == 5 else None
            entries.append((parts[0], parts[1], axis))
        maps[name[len("articula:"):]] = entries
    return maps


class Frame:
    """One frame's articula columns: S[prefix + name] for the states, T[name] for torques."""

    def __init__(self, states, torques, k):
        self.s = {n: c[k] for n, c in states.items()}
        # torque columns are `tau:<coord>` (articula's one CSV naming scheme)
        self.t = {n[len("tau:"):]: c[k] for n, c in torques.items() if n.startswith("tau:")}


def free_root(m, d, jid, entries, f, pairs):
    """Sets a free joint's qpos/qvel/qacc; returns a function that appends (articula, mujoco)
    torque pairs once qfrc_inverse is known."""
    qa, va = m.jnt_qposadr[jid], m.jnt_dofadr[jid]
    p0, q0 = m.qpos0[qa:qa + 3].copy(), m.qpos0[qa + 3:qa + 7].copy()
    r0 = quat_to_mat(q0)
    if entries[0][1] == "free":
        j = entries[0][0]
        x = np.array([f.s[f"q:{j}:{c}"] for c in "xyz"])
        qx, qy, qz, qw = (f.s[f"q:{j}:{c}"] for c in ("qx", "qy", "qz", "qw"))
        qrel = np.array([qw, qx, qy, qz])
        qrel /= np.linalg.norm(qrel)
        quat = np.zeros(4)
        mujoco.mju_mulQuat(quat, q0, qrel)
        r = quat_to_mat(quat)
        v = np.array([f.s[f"v:{j}:v{c}"] for c in "xyz"])
        w = np.array([f.s[f"v:{j}:w{c}"] for c in "xyz"])
        a = np.array([f.s[f"a:{j}:v{c}"] for c in "xyz"])
        dw = np.array([f.s[f"a:{j}:w{c}"] for c in "xyz"])
        d.qpos[qa:qa + 3] = p0 + r0 @ x
        d.qpos[qa + 3:qa + 7] = quat
        d.qvel[va:va + 3] = r @ v
        d.qvel[va + 3:va + 6] = w
        d.qacc[va:va + 3] = r @ (a + np.cross(w, v))
        d.qacc[va + 3:va + 6] = dw

        def forces():
            fl = r.T @ d.qfrc_inverse[va:va + 3]
            n = d.qfrc_inverse[va + 3:va + 6]
            for k, c in enumerate("xyz"):
                pairs.append((f"{j}:v{c}", f.t[f"{j}:v{c}"], fl[k]))
                pairs.append((f"{j}:w{c}", f.t[f"{j}:w{c}"], n[k]))
        return forces
    # the euler model: slides then hinges
    slides = [(n, ax) for n, kind, ax in entries if kind == "slide"]
    hinges = [(n, ax) for n, kind, ax in entries if kind == "hinge"]
    pos = p0 + r0 @ sum(f.s[f"q:{n}"] * ax for n, ax in slides)
    vel = r0 @ sum(f.s[f"v:{n}"] * ax for n, ax in slides)
    acc = r0 @ sum(f.s[f"a:{n}"] * ax for n, ax in slides)
    rs = [rot(ax, f.s[f"q:{n}"]) for n, ax in hinges]
    r = r0.copy()
    w, dw = np.zeros(3), np.zeros(3)
    for (n, ax), rk in zip(hinges, rs):
        r = r @ rk
        s = ax * f.s[f"v:{n}"]
        w = rk.T @ w + s
        dw = rk.T @ dw + ax * f.s[f"a:{n}"] + np.cross(w, s)
    d.qpos[qa:qa + 3] = pos
    d.qpos[qa + 3:qa + 7] = mat_to_quat(r)
    d.qvel[va:va + 3] = vel
    d.qvel[va + 3:va + 6] = w
    d.qacc[va:va + 3] = acc
    d.qacc[va + 3:va + 6] = dw

    def forces():
        fw = d.qfrc_inverse[va:va + 3]
        n = d.qfrc_inverse[va + 3:va + 6]
        for name, ax in slides:
            pairs.append((name, f.t[name], (r0 @ ax) @ fw))
        for k, (name, ax) in enumerate(hinges):
            after = np.eye(3)
            for rk in rs[k + 1:]:
                after = after @ rk
            pairs.append((name, f.t[name], (after.T @ ax) @ n))
    return forces


def inner_free_slides(m, ball):
    """The slides `BALL:x|y|z` the MJCF writes before a ball joint for a free joint below the
    root: [(component, qpos address, dof address)], empty if none."""
    out = []
    for c in "xyz":
        j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"{ball}:{c}")
        if j < 0:
            return []
        out.append((c, m.jnt_qposadr[j], m.jnt_dofadr[j]))
    return out


def set_frame(m, d, f, roots, pairs):
    """Sets d.qpos/qvel/qacc from frame f; returns the functions that collect torque pairs."""
    collect = []
    balls = {m.joint(j).name for j in range(m.njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL}
    for j in range(m.njnt):
        name = m.joint(j).name
        qa, va, kind = m.jnt_qposadr[j], m.jnt_dofadr[j], m.jnt_type[j]
        if kind == mujoco.mjtJoint.mjJNT_FREE:
            collect.append(free_root(m, d, j, roots[name], f, pairs))
        elif kind == mujoco.mjtJoint.mjJNT_BALL:
            qx, qy, qz, qw = (f.s[f"q:{name}:{c}"] for c in ("qx", "qy", "qz", "qw"))
            d.qpos[qa:qa + 4] = np.array([qw, qx, qy, qz])
            for k, c in enumerate("xyz"):
                d.qvel[va + k] = f.s[f"v:{name}:w{c}"]
                d.qacc[va + k] = f.s[f"a:{name}:w{c}"]
            slides = inner_free_slides(m, name)
            if slides:
                # a free joint below the root: three slides (position in the parent) then this
                # ball; articula's linear v is in the child frame, MuJoCo's slide rates in the
                # parent's: pdot = R v, pddot = R (a + w x v); forces f = R^T (slide forces)
                r = quat_to_mat(d.qpos[qa:qa + 4])
                v = np.array([f.s[f"v:{name}:v{c}"] for c in "xyz"])
                acc = np.array([f.s[f"a:{name}:v{c}"] for c in "xyz"])
                w = np.array([f.s[f"v:{name}:w{c}"] for c in "xyz"])
                pd, pdd = r @ v, r @ (acc + np.cross(w, v))
                for k, (c, sq, sv) in enumerate(slides):
                    d.qpos[sq] = f.s[f"q:{name}:{c}"]
                    d.qvel[sv] = pd[k]
                    d.qacc[sv] = pdd[k]

                def lin(name=name, slides=slides, r=r):
                    fl = r.T @ np.array([d.qfrc_inverse[sv] for _, _, sv in slides])
                    for k, c in enumerate("xyz"):
                        pairs.append((f"{name}:v{c}", f.t[f"{name}:v{c}"], fl[k]))
                collect.append(lin)

            def ball(name=name, va=va):
                for k, c in enumerate("xyz"):
                    pairs.append((f"{name}:w{c}", f.t[f"{name}:w{c}"], d.qfrc_inverse[va + k]))
            collect.append(ball)
        elif name.rsplit(":", 1)[0] in balls:
            continue  # a slide of a free joint below the root, set with its ball
        else:
            d.qpos[qa] = f.s[f"q:{name}"]
            d.qvel[va] = f.s[f"v:{name}"]
            d.qacc[va] = f.s[f"a:{name}"]

            def one(name=name, va=va):
                pairs.append((name, f.t[name], d.qfrc_inverse[va]))
            collect.append(one)
    return collect


def run(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("take")
    p.add_argument("--articula", default=os.environ.get("ARTICULA", "target/release/articula"))
    p.add_argument("--tol", type=float, default=1e-8)
    p.add_argument("--keep", help="write the MJCF, states and torques here")
    p.add_argument("--format", choices=["mjcf", "urdf"], default="mjcf",
                   help="the export MuJoCo loads (urdf: the euler model only; its root is "
                        "articula's own 3 slides + 3 hinges, so every coordinate maps 1:1)")
    extra = []
    if "--" in argv:
        k = argv.index("--")
        argv, extra = argv[:k], argv[k + 1:]
    a = p.parse_args(argv)
    a.opts = extra
    out = a.keep or tempfile.mkdtemp(prefix="check_mujoco_")
    os.makedirs(out, exist_ok=True)
    model_file = "model.xml" if a.format == "mjcf" else "model.urdf"
    xml, states, tau = (os.path.join(out, n) for n in (model_file, "states.csv", "id.csv"))
    art = [a.articula]
    for cmd in (["export", a.format, a.take, "-o", xml],
                ["export", "states", a.take, "-o", states],
                ["id", a.take, "--contact", "none", "-o", tau]):
        subprocess.run(art + cmd + a.opts, check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
    m = mujoco.MjModel.from_xml_path(xml)
    m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    d = mujoco.MjData(m)
    s, n = read_csv(states)
    t, nt = read_csv(tau)
    assert n == nt, f"{n} state rows, {nt} torque rows"
    roots = root_maps(m)
    worst_rel, worst_abs, where = 0.0, 0.0, None
    compared = set()
    for k in range(n):
        f = Frame(s, t, k)
        pairs = []
        collect = set_frame(m, d, f, roots, pairs)
        mujoco.mj_inverse(m, d)
        for c in collect:
            c()
        scale = max(abs(x) for _, x, _ in pairs)
        for name, x, y in pairs:
            compared.add(name)
            rel = abs(x - y) / scale
            worst_abs = max(worst_abs, abs(x - y))
            if rel > worst_rel:
                worst_rel, where = rel, (k, name, x, y)
    # every torque column `tau:<coord>` must have been compared
    missing = [c for c in t if c != "time" and c[len("tau:"):] not in compared]
    print(f"{a.take} {' '.join(a.opts)} ({a.format}): MuJoCo {mujoco.__version__}, nq {m.nq}, "
          f"nv {m.nv}, nu {m.nu}, ngeom {m.ngeom}, gravity {m.opt.gravity}, {n} frames, {len(compared)} coordinates compared"
          + (f", NOT compared: {missing}" if missing else ""))
    print(f"  max |tau_mujoco - tau_articula| / max|tau_articula| (per frame) = {worst_rel:.3e}; "
          f"max abs {worst_abs:.3e}")
    if where:
        k, name, x, y = where
        print(f"  worst at frame {k}, {name}: articula {x!r}, mujoco {y!r}")
    ok = worst_rel <= a.tol and not missing
    print("  OK" if ok else f"  FAIL (tolerance {a.tol})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
