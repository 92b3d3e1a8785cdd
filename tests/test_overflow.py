"""Directions and lengths read without overflow, and non-finite values refused where the
model is built: a vector whose norm overflows when squared (``[1e200, 0, 0]``) is still the
direction it points in, and finite inputs that make a non-finite number while the model is
built are refused at their key (``fvbeam.geometry.norm``, ``direction``,
``sliders.app.errors.Problems.attempt``)."""

import tomllib

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from test_scenes import SCENES

from fvbeam.geometry import direction, inertia3, norm
from sliders.app.errors import NON_FINITE, SceneError
from sliders.app.model import Model
from sliders.app.scene import parse_scene

entries = st.floats(min_value=-1e3, max_value=1e3, allow_nan=False).filter(
    lambda x: x == 0 or abs(x) > 1e-3
)
vectors = st.lists(entries, min_size=3, max_size=3).filter(lambda v: any(v))


@given(vectors, st.integers(min_value=-960, max_value=960))
def test_a_length_scales_exactly_with_its_vector(v, k):
    """Scaling by a power of two is exact in floating point, and so is the scaled norm's
    division by the largest entry: ``|2^k v| = 2^k |v|`` to the last bit, for vectors up to
    ``1e3 2^960 ~ 1e292`` (whose squares overflow) and down to ``1e-3 2^-960``."""
    scale = 2.0**k
    assert norm(np.array(v) * scale) == scale * norm(v)
    assert np.array_equal(direction(np.array(v) * scale, "v"), direction(v, "v"))


def test_norm_of_rows_and_of_zero():
    rows = np.array([[3e200, 4e200, 0.0], [0.0, 0.0, 0.0], [3e-200, 0.0, 4e-200]])
    assert np.allclose(norm(rows), [5e200, 0.0, 5e-200], rtol=1e-15, atol=0)
    with pytest.raises(ValueError, match="non-zero"):
        direction([0.0, 0.0, 0.0], "normal")


def test_an_inertia_of_large_entries_is_checked_on_its_scale():
    """Eigenvalues of ``[[1e300, 2e300], [2e300, 1e300]]`` (an indefinite matrix, -1e300 and
    3e300) overflow when computed unscaled; scaled, the matrix is refused as it should be."""
    J = [[1e300, 2e300, 0.0], [2e300, 1e300, 0.0], [0.0, 0.0, 1e300]]
    with pytest.raises(ValueError, match="positive semi-definite"):
        inertia3(J, "inertia")
    assert inertia3([1e300, 1e300, 1e300], "inertia")[0, 0] == 1e300


def fig1(**study) -> dict:
    data = tomllib.loads((SCENES / "fig1_cantilever.toml").read_text())
    data["study"] = study
    return data


def test_a_sweep_direction_whose_norm_overflows_moves_along_it():
    """``direction = [1e200, 0, 0]`` moves the beam along x as ``[1, 0, 0]`` does (its norm
    overflowed to inf: every offset was 0)."""
    parameter = {"kind": "translation", "move": ["cantilever"], "direction": [1e200, 0.0, 0.0]}
    data = fig1(kind="sweep", parameter=parameter, values=[0.0, 0.25])
    model = Model(parse_scene(data, SCENES), "test.toml")
    assert np.array_equal(model.offset(0.25), [0.25, 0.0, 0.0])


def test_a_tyre_normal_whose_norm_overflows_is_its_direction():
    """A ground normal ``[0, 0, 1e200]`` was normalised to ``[0, 0, 0]`` (a constant vertical
    load and a wheel that never spins); it is the unit z axis."""
    data = tomllib.loads((SCENES / "landing_gear.toml").read_text())
    tyre = next(f for f in data["force"] if f["kind"] == "tyre")
    tyre["normal"], tyre["forward"] = [0.0, 0.0, 1e200], [1e-200, 0.0, 0.0]
    model = Model(parse_scene(data, SCENES), "test.toml")
    built = next(f for f in model.forces if f.name == "tyre")
    assert np.array_equal(built.normal, [0.0, 0.0, 1.0])
    assert np.array_equal(built.forward, [1.0, 0.0, 0.0])


@pytest.mark.parametrize(
    "start,end",
    [
        ([-1.5e308, 0.0, 0.0], [1.5e308, 0.0, 0.0]),  # end - start overflows
        ([0.0, 0.0, 0.0], [1e200, 1e200, 0.0]),  # lengths are finite, the stiffness is not
    ],
)
def test_finite_inputs_that_build_non_finite_numbers_are_refused_at_their_key(start, end):
    data = tomllib.loads((SCENES / "fig1_cantilever.toml").read_text())
    data["beam"][0]["straight"].update(start=start, end=end)
    data["load"] = []
    data["study"] = {"kind": "static"}
    with pytest.raises(SceneError) as info:
        Model(parse_scene(data, SCENES), "test.toml")
    (problem,) = info.value.problems
    assert problem.path == "beam[0]" and NON_FINITE in problem.message
