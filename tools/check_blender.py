#!/usr/bin/env python3
"""Blender reads articula's BVH and glTF as articula means them.

For each take: articula writes it as BVH (`smooth --smooth none`, portable BVH), as glTF
(`export gltf`) and its joint centres (`export positions`, m, the take's axes). Blender (in
background mode) imports both with its own importers, and every bone head's world position at
sampled frames must equal articula's within TOL_M (the BVH's: articula's own reading of that
BVH, `export positions OUT.bvh --keep-first-frame`; the glTF's: the take's joint centres):
- BVH: imported with no axis change (forward Y, up Z: Blender's own axes) and scale
  `scale_to_m`, so heads are the take's positions; Blender *replaces* the OFFSET with the
  position channels, three.js adds them: portable BVH makes both right.
- glTF: Blender's importer turns glTF's +Y up into its +Z up, (x, y, z) → (x, −z, y), after
  articula's turn of the take's up axis to +Y (src/pipeline/animation.rs, TO_Y_UP).
Besides the takes given, a synthetic take whose root position channels replace the OFFSET is
always checked (the one tools/check_threejs.mjs writes, read from there).

Blender 3.4's BVH importer opens files with mode 'rU', which Python 3.11 refuses, and its glTF
importer uses `numpy.bool`, which numpy 1.24 removed; this script patches the importer's `open`
to drop the 'U' and sets `numpy.bool = bool` for the run (no file of Blender's is changed).

usage: python3 tools/check_blender.py ARTICULA [TAKE...]   (needs `blender` on PATH)
Exit status 1 on a disagreement, 2 when Blender or articula cannot run.
"""

import json
import os
import subprocess
import sys
import tempfile

TOL_M = 1e-4  # 0.1 mm
UP = {  # rows of C: glTF axes from the take's (TO_Y_UP)
    "x": [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
    "y": [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
    "z": [[1, 0, 0], [0, 0, 1], [0, -1, 0]],
}


def inside_blender(job_path):
    """Imports the job's files and writes the bone heads at the asked frames."""
    import builtins

    import bpy
    import io_anim_bvh.import_bvh as import_bvh

    import_bvh.open = lambda path, mode="r", *a, **k: builtins.open(
        path, mode.replace("U", ""), *a, **k
    )
    # Blender 3.4's glTF importer uses `np.bool`, gone from Debian's numpy 1.24
    import numpy

    if "bool" not in numpy.__dict__:
        numpy.bool = bool
    with open(job_path) as f:
        job = json.load(f)
    scene = bpy.context.scene
    out = {}
    for kind in ("bvh", "glb"):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        scene = bpy.context.scene
        scene.render.fps = job["fps"]
        if kind == "bvh":
            bpy.ops.import_anim.bvh(
                filepath=job["bvh"],
                axis_forward="Y",
                axis_up="Z",
                global_scale=job["scale_to_m"],
                frame_start=1,
                use_fps_scale=False,
            )
        else:
            bpy.ops.import_scene.gltf(filepath=job["glb"])
        arm = next(o for o in scene.objects if o.type == "ARMATURE")
        heads = {}
        for k, frame in zip(job["frames"], job[f"{kind}_frames"]):
            whole = int(frame)
            scene.frame_set(whole, subframe=frame - whole)
            bpy.context.view_layer.update()
            heads[str(k)] = {
                pb.name: list(arm.matrix_world @ pb.head) for pb in arm.pose.bones
            }
        out[kind] = heads
    with open(job["out"], "w") as f:
        json.dump(out, f)


def blender_env():
    """The environment without pyenv: Blender's embedded Python takes its prefix from the
    first python3 on PATH, and a pyenv one hides Debian's numpy from the glTF importer."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYENV")}
    env["PATH"] = os.pathsep.join(
        p for p in env.get("PATH", "").split(os.pathsep) if ".pyenv" not in p
    )
    return env


def run(articula, *args):
    return subprocess.run(
        [articula, *args], check=True, capture_output=True, text=True
    ).stdout


def replace_take(work):
    """The synthetic replace-convention take of tools/check_threejs.mjs."""
    import math

    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "check_threejs.mjs")) as f:
        src = f.read()
    text = src.split("const text = `", 1)[1].split("`;", 1)[0]
    rows = []
    for k in range(30):
        s, c = math.sin(k / 5), math.cos(k / 5)
        vals = [20 + 30 * s, 95 + 2 * c, 40 + 10 * k, 5 * s, 20 * c, 3, 10 * s, 0, 0,
                30 * s, 0, 0, -10 * s, 0, 0, 30 * c, 0, 0, 5, 5 * c, 0]
        rows.append(" ".join(f"{v:.4f}" for v in vals))
    text = text.replace("${rows.length}", str(len(rows))).replace("${rows.join('\\n')}", "\n".join(rows))
    path = os.path.join(work, "replace_root.bvh")
    with open(path, "w") as f:
        f.write(text)
    return path


def positions_csv(path):
    """Joint names and rows [time, x, y, z per joint] of `export positions`."""
    with open(path) as f:
        head, *rows = [line.strip().split(",") for line in f if line.strip()]
    # `pos:<joint>:x|y|z` (articula's one column scheme)
    names = [head[i].removeprefix("pos:")[:-2] for i in range(1, len(head), 3)]
    return names, [[float(x) for x in r] for r in rows]


def check(articula, take, work):
    stem = os.path.splitext(os.path.basename(take))[0]
    try:
        info = json.loads(run(articula, "info", take, "--json"))
    except subprocess.CalledProcessError as e:
        # a take articula refuses (with its clear error) has no output to check
        print(f"skip Blender {stem}: articula refuses it: {e.stderr.strip().splitlines()[-1]}")
        return True
    files = {e: os.path.join(work, f"{stem}.{e}") for e in ("bvh", "glb", "csv")}
    run(articula, "smooth", take, "--smooth", "none", "-o", files["bvh"])
    run(articula, "export", "gltf", take, "-o", files["glb"])
    run(articula, "export", "positions", take, "-o", files["csv"])
    # the BVH against articula's reading of that same file (a joint `smooth` welds as a prop
    # keeps its rest rotation there), the glTF against the take's
    own_csv = os.path.join(work, f"{stem}.out.csv")
    run(articula, "export", "positions", files["bvh"], "--keep-first-frame", "-o", own_csv)
    names, rows = positions_csv(files["csv"])
    _, own_rows = positions_csv(own_csv)
    if len(own_rows) != len(rows):
        raise RuntimeError(f"{stem}: articula reads {len(own_rows)} frames back, wrote {len(rows)}")
    n = len(rows)
    frames = sorted({0, n // 3, 2 * n // 3, n - 1})
    dt = info["frame_time"]
    fps = max(1, round(1 / dt))
    job = {
        "bvh": files["bvh"],
        "glb": files["glb"],
        "scale_to_m": info["scale_to_m"],
        "fps": fps,
        "frames": frames,
        # BVH frame k at scene frame 1 + k; glTF key k at its time × fps
        "bvh_frames": [1 + k for k in frames],
        "glb_frames": [rows[k][0] * fps for k in frames],
        "out": os.path.join(work, f"{stem}.heads.json"),
    }
    job_path = os.path.join(work, f"{stem}.job.json")
    with open(job_path, "w") as f:
        json.dump(job, f)
    done = subprocess.run(
        ["blender", "-b", "--factory-startup", "--python-exit-code", "2",
         "--python", os.path.abspath(__file__), "--", "--inside", job_path],
        capture_output=True, text=True, env=blender_env(),
    )
    if done.returncode != 0 or not os.path.exists(job["out"]):
        print(done.stdout[-2000:], done.stderr[-2000:], file=sys.stderr)
        raise RuntimeError(f"blender failed on {stem} (status {done.returncode})")
    with open(job["out"]) as f:
        heads = json.load(f)
    c = UP[info["up"]]
    ok = True
    for kind in ("bvh", "glb"):
        worst, where = 0.0, ""
        for k in frames:
            got = heads[kind][str(k)]
            for j, name in enumerate(names):
                p = (rows if kind == "glb" else own_rows)[k][1 + 3 * j: 4 + 3 * j]
                if kind == "glb":
                    g = [sum(c[i][m] * p[m] for m in range(3)) for i in range(3)]
                    p = [g[0], -g[2], g[1]]  # Blender's glTF import: Y up → Z up
                if name not in got:
                    raise RuntimeError(f"{stem}.{kind}: bone {name} missing in Blender")
                e = sum((a - b) ** 2 for a, b in zip(got[name], p)) ** 0.5
                if e > worst:
                    worst, where = e, f"{name} at frame {k}"
        passed = worst <= TOL_M
        ok = ok and passed
        print(f"{'ok  ' if passed else 'FAIL'} Blender {kind} {stem}: {len(names)} joints, "
              f"frames {','.join(map(str, frames))}: max |Δ| {worst * 1000:.4f} mm"
              f"{f' ({where})' if worst > 0 else ''} (tolerance {TOL_M * 1000} mm)")
    return ok


def main():
    if "--inside" in sys.argv:
        inside_blender(sys.argv[sys.argv.index("--inside") + 1])
        return 0
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    articula, takes = sys.argv[1], sys.argv[2:]
    work = tempfile.mkdtemp(prefix="articula-blender-")
    ok = True
    for take in [replace_take(work), *takes]:
        try:
            ok = check(articula, take, work) and ok
        except (RuntimeError, subprocess.CalledProcessError) as e:
            print(f"FAIL Blender {take}: {e}")
            ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
