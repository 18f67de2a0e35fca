"""Model.from_urdf: rnea and crba equal `articula id --urdf` and `articula mass-matrix --urdf`
on random states bit for bit (the same library path), and the algorithms agree with each
other: crba's columns are rnea's differences, aba inverts rnea."""

import numpy as np

import articula
from conftest import REPO, read_csv

URDF = REPO / "data" / "arm7.urdf"


def states(model, rows=9, seed=7):
    rng = np.random.default_rng(seed)
    return (
        rng.uniform(-1.5, 1.5, (rows, model.nq)),
        rng.uniform(-2.0, 2.0, (rows, model.nv)),
        rng.uniform(-5.0, 5.0, (rows, model.nv)),
    )


def write_states(path, model, q, v, a):
    header = ["time"] + [f"q:{n}" for n in model.q_names] + [f"v:{n}" for n in model.v_names]
    header += [f"a:{n}" for n in model.v_names]
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for k in range(len(q)):
            row = [0.01 * k, *q[k], *v[k], *a[k]]
            f.write(",".join(repr(float(x)) for x in row) + "\n")


def test_rnea_equals_cli(cli, tmp_path):
    m = articula.Model.from_urdf(URDF)
    q, v, a = states(m)
    write_states(tmp_path / "s.csv", m, q, v, a)
    cli("id", "--urdf", URDF, "--states", tmp_path / "s.csv", "-o", tmp_path / "id.csv")
    header, values = read_csv(tmp_path / "id.csv")
    assert header[1:] == [f"tau:{n}" for n in m.v_names]
    assert np.array_equal(m.rnea(q, v, a), values[:, 1:])
    # one state as a 1-D array is one row
    assert np.array_equal(m.rnea(q[3], v[3], a[3]), values[3, 1:])


def test_crba_equals_cli_and_rnea_columns(cli, tmp_path):
    m = articula.Model.from_urdf(URDF)
    q, v, a = states(m)
    write_states(tmp_path / "s.csv", m, q, v, a)
    cli("mass-matrix", "--urdf", URDF, "--states", tmp_path / "s.csv", "-o", tmp_path / "m.csv")
    _, values = read_csv(tmp_path / "m.csv")
    big = m.crba(q)
    assert big.shape == (len(q), m.nv, m.nv)
    assert np.array_equal(big.reshape(len(q), -1), values[:, 1:])
    # column j of M(q) is rnea(q, 0, e_j) − rnea(q, 0, 0)
    zero = np.zeros(m.nv)
    bias = m.rnea(q[0], zero, zero)
    for j in range(m.nv):
        e = np.eye(m.nv)[j]
        np.testing.assert_allclose(big[0][:, j], m.rnea(q[0], zero, e) - bias, atol=1e-10)


def test_aba_inverts_rnea():
    m = articula.Model.from_urdf(URDF)
    q, v, a = states(m)
    tau = m.rnea(q, v, a)
    np.testing.assert_allclose(m.aba(q, v, tau), a, rtol=1e-9, atol=1e-9)
