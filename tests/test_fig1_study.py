"""The Figure 1 study (``studies/fig1_tip_response.py``) against the paper's closed forms."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from fvbeam import closed_forms
from studies.fig1_tip_response import main

HEADER = ["formulation", "xi_over_L", "v_flexural", "v_shear", "phi"]
FORMULATIONS = ["exact", "fv2", "fv3", "galerkin-p1", "galerkin-p2"]
STATIONS = np.arange(101) / 100


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    path = tmp_path_factory.mktemp("fig1")
    main(["--out", str(path)])
    return path


@pytest.fixture(scope="module")
def lines(out):
    """The CSV read back as lists of strings, header first."""
    with open(out / "fig1_tip_response.csv", newline="") as f:
        return list(csv.reader(f))


@pytest.fixture(scope="module")
def table(lines):
    """``{formulation: (xi_over_L, v_flexural, v_shear, phi)}`` as float arrays."""
    rows = lines[1:]
    return {
        name: np.array([[float(x) for x in r[1:]] for r in rows if r[0] == name]).T
        for name in {r[0] for r in rows}
    }


def test_layout(lines, table):
    assert lines[0] == HEADER
    assert len(lines) == 1 + len(FORMULATIONS) * len(STATIONS)
    assert sorted(table) == sorted(FORMULATIONS)
    for name in FORMULATIONS:
        np.testing.assert_array_equal(table[name][0], STATIONS)


@pytest.mark.parametrize("name", ["exact", "fv2", "fv3"])
def test_closed_forms(table, name):
    closed_form = getattr(closed_forms, f"cantilever_{name}")
    xi, *values = table[name]
    # exact rows are the closed form itself written with repr: only round-off of the print.
    # fv rows: the closed forms are exact for one element (paper Secs. 5.2-5.3); 1e-10
    # leaves margin over the ~1e-15 round-off of the solves and of the flexural/shear split.
    tol = 1e-14 if name == "exact" else 1e-10
    np.testing.assert_allclose(values, closed_form(xi), rtol=tol, atol=tol)


def test_tip_load(table):
    exact = table["exact"][1:, -1]
    # paper Sec. 5.4: "the three-node beam recovers the exact solution" for a tip force;
    # 1e-10 as above (round-off only).
    np.testing.assert_allclose(table["fv3"][1:, -1], exact, rtol=1e-10, atol=1e-10)
    fv2_flexural = table["fv2"][1, -1]
    # paper Sec. 5.2 at xi = L: v = 1/4 + 1 against exact 1/3 + 1; 1e-10: round-off only.
    assert fv2_flexural == pytest.approx(0.25, abs=1e-10)
    assert abs(fv2_flexural - exact[0]) > 0.08
    # paper Sec. 5.4: "even the two-node beam recovers the exact rotation" at the extremity.
    assert table["fv2"][3, -1] == pytest.approx(exact[2], abs=1e-10)


def test_galerkin_p2_tip(table):
    # a P2 Timoshenko element with 2-point (reduced) integration is exact for a tip force
    # (linear moment, constant shear); 1e-10: round-off only.
    np.testing.assert_allclose(
        table["galerkin-p2"][1:, -1], table["exact"][1:, -1], rtol=1e-10, atol=1e-10
    )


def test_png(out):
    data = (out / "fig1_tip_response.png").read_bytes()
    assert data.startswith(b"\x89PNG\r\n\x1a\n")
    # a three-panel figure with five lines each is far above 10 kB; an empty one is not.
    assert len(data) > 10_000
