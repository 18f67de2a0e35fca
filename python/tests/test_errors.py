"""Bad input is a Python exception carrying articula's message (file, line, what was
expected), never a crash; options a command would ignore are refused, as on the command line."""

import pytest

import articula
from conftest import DEMO


def test_missing_file_names_it(tmp_path):
    with pytest.raises(articula.ArticulaError, match="nope.bvh"):
        articula.load(tmp_path / "nope.bvh")


def test_corrupt_take_names_file_and_line(tmp_path):
    bad = tmp_path / "broken.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n")
    with pytest.raises(articula.ArticulaError, match=r"broken\.bvh:\d+"):
        articula.load(bad)


def test_bad_option_value_is_the_flag_message():
    with pytest.raises(articula.ArticulaError, match="--mass"):
        articula.load(DEMO, mass=-3)
    with pytest.raises(articula.ArticulaError, match="--smooth"):
        articula.load(DEMO, smooth="wobbly")


def test_unknown_option_is_a_type_error():
    with pytest.raises(TypeError, match="take options are"):
        articula.load(DEMO, masss=80)


def test_option_a_command_ignores_is_refused():
    take = articula.load(DEMO, contact="feet")
    with pytest.raises(articula.ArticulaError, match="--contact has no effect on `articula simulate`"):
        take.simulate(duration=0.1)


def test_consistent_without_contact_is_refused():
    with pytest.raises(articula.ArticulaError, match="--consistent"):
        articula.load(DEMO, contact="none").inverse_dynamics(consistent="on")


def test_model_shape_mismatch_is_a_value_error():
    from conftest import REPO

    m = articula.Model.from_urdf(REPO / "data" / "arm7.urdf")
    with pytest.raises(ValueError, match="expected 7 numbers per row"):
        m.rnea([0.0] * 3, [0.0] * 7, [0.0] * 7)
