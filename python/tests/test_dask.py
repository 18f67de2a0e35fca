"""The module under Dask gives `articula batch`'s summary.

`client.map(process_take, paths)` on a LocalCluster of two worker processes computes, per
take, the row `articula batch DIR -o OUT -- id --contact auto` writes to summary.csv: take,
status, frames, and the peak |x| and RMS of the columns the batch summarises (read from its
header, so the test follows whatever the batch reports). A take that fails is a failed row in
both. The takes: the shared ones (ARTICULA_REAL_TAKES), else the demo walk, generated walks
and a corrupt file.
"""

import csv
import os
import shutil
import sys
from pathlib import Path

import pytest

from conftest import DEMO, real_takes

distributed = pytest.importorskip("distributed")
cloudpickle = pytest.importorskip("cloudpickle")


def process_take(path, root, columns):
    """One summary row of a take, as `articula batch … -- id --contact auto` gives it."""
    import articula

    row = {"take": os.path.relpath(path, root), "status": "ok", "frames": "", "figures": {}}
    try:
        r = articula.load(path, contact="auto").inverse_dynamics()
    except articula.ArticulaError as e:
        row["status"] = "failed"
        row["error"] = str(e)
        return row
    row["frames"] = str(len(r.time))
    peaks, rms = r.peaks(), r.rms()
    row["figures"] = {c: (peaks[c], rms[c]) for c in columns if c in peaks}
    return row


def corpus(cli, folder: Path):
    """The demo, two generated walks and a corrupt take in `folder`."""
    (folder / "gen").mkdir(parents=True)
    shutil.copy(DEMO, folder / "demo_walk.bvh")
    cli("generate", "walk", "-o", folder / "gen" / "slow.bvh", "--fps", "60", "--duration", "2")
    cli("generate", "walk", "-o", folder / "gen" / "tall.bvh", "--scale", "1.1", "--duration", "1.5")
    (folder / "broken.bvh").write_text("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n")
    return folder


def test_dask_map_equals_batch_summary(cli, tmp_path):
    shared = real_takes()
    root = shared[0].parent if shared else corpus(cli, tmp_path / "takes")
    out = tmp_path / "out"
    cli("batch", root, "-o", out, "--jobs", "2", "--", "id", "--contact", "auto", check=False)
    with open(out / "summary.csv", newline="") as f:
        reader = csv.DictReader(f)
        header = reader.fieldnames
        batch = {r["take"]: r for r in reader}
    columns = [h[len("peak:"):] for h in header if h.startswith("peak:")]
    assert columns, f"the batch summarised no columns: {header}"

    paths = sorted(str(p) for p in Path(root).rglob("*.bvh"))
    assert len(paths) == len(batch)
    # the workers are separate processes: ship process_take by value, not by module name
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        futures = client.map(process_take, paths, root=str(root), columns=columns)
        rows = client.gather(futures)

    assert any(r["status"] == "ok" for r in rows)
    for r in rows:
        b = batch[r["take"]]
        assert r["status"] == b["status"], (r, b["failure"])
        assert r["frames"] == b["frames"], r["take"]
        for c in columns:
            peak, rms = b[f"peak:{c}"], b[f"rms:{c}"]
            if peak == "":
                assert c not in r["figures"], (r["take"], c)
            else:
                assert r["figures"][c] == (float(peak), float(rms)), (r["take"], c)
