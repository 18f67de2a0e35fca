"""The module's results are the command line's CSVs, bit for bit.

Each command runs once through `articula COMMAND … -o FILE.csv` and once through the module
with the same options; the column names, times and every number must be the same doubles
(the CSV holds shortest round-trip numbers, so reading it back loses nothing).
"""

import pytest

import articula
from conftest import DEMO, assert_same_table, real_takes


@pytest.mark.parametrize(
    "flags, options",
    [
        ([], {}),
        (["--contact", "none"], {"contact": "none"}),
        (["--joints", "ball", "--mass", "62.5", "--smooth", "none"],
         {"joints": "ball", "mass": 62.5, "smooth": "none"}),
    ],
)
def test_inverse_dynamics_equals_cli(cli, tmp_path, flags, options):
    out = tmp_path / "id.csv"
    cli("id", DEMO, *flags, "-o", out)
    assert_same_table(articula.load(DEMO, **options).inverse_dynamics(), out)


def test_inverse_dynamics_with_residual_reduction_equals_cli(cli, tmp_path):
    out = tmp_path / "id.csv"
    cli("id", DEMO, "--consistent", "on", "-o", out)
    r = articula.load(DEMO).inverse_dynamics(consistent="on")
    assert_same_table(r, out)
    assert r.summary is not None and "after" in r.summary


def test_anatomy_equals_cli(cli, tmp_path):
    out = tmp_path / "anatomy.csv"
    cli("anatomy", DEMO, "-o", out)
    assert_same_table(articula.load(DEMO).anatomy(), out)


def test_simulate_equals_cli(cli, tmp_path):
    out = tmp_path / "sim.csv"
    cli("simulate", DEMO, "--duration", "0.25", "--kp", "300", "--kv", "LeftLeg=50", "-o", out)
    r = articula.load(DEMO).simulate(duration=0.25, kp=300, kv={"LeftLeg": 50})
    assert_same_table(r, out)
    assert r.summary["integrator"]


@pytest.mark.parametrize("what", ["states", "positions", "grf"])
def test_export_equals_cli(cli, tmp_path, what):
    out = tmp_path / f"cli_{what}.csv"
    cli("export", what, DEMO, "-o", out)
    r = articula.load(DEMO).export(tmp_path / f"py_{what}.csv", what)
    assert_same_table(r, out)
    assert (tmp_path / f"py_{what}.csv").read_bytes() == out.read_bytes()


def test_take_attributes_match_info(cli):
    take = articula.load(DEMO)
    info = take.info()
    assert take.frames == info["frames"] == len(take.time)
    assert len(take.coordinates) == info["nq"]
    assert take.time[1] - take.time[0] == pytest.approx(info["frame_time"])


def test_peaks_and_pandas():
    r = articula.load(DEMO).inverse_dynamics()
    peaks = r.peaks()
    assert list(peaks) == r.columns
    col = r.columns.index("residual:fz")
    assert peaks["residual:fz"] == abs(r.values[:, col]).max()
    pd = pytest.importorskip("pandas")
    df = r.to_pandas()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == r.columns and df.index.name == "time"
    assert df.shape == r.values.shape


@pytest.mark.parametrize("take", real_takes(), ids=lambda p: p.name)
def test_real_take_inverse_dynamics_equals_cli(cli, tmp_path, take):
    out = tmp_path / "id.csv"
    cli("id", take, "--contact", "auto", "-o", out)
    assert_same_table(articula.load(take, contact="auto").inverse_dynamics(), out)
