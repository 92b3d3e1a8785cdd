"""The scales of the summary's event rules (:mod:`sliders.app.events`).

A spin-up (``omega R0`` reaching ``fraction`` of the axle's forward speed ``u``) is counted
only while ``u`` is above the tyre's ``speed_eps`` (:func:`sliders.app.events.spin_up`): a
landing gear dropped with no forward speed, whose ``u`` and ``omega`` are round-off, has no
spin-up, and so no spring-back (a peak after it) and no spring-back frequency.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import tomli_w
from test_cli_properties import command, small

from sliders.app.events import spin_up


def test_the_spin_up_counts_only_above_the_tyres_speed_eps():
    """``omega R0 - 0.99 u`` linear in time crosses zero where the straight line does (the
    interpolation is exact for it), and not where ``u`` is below ``speed_eps``."""
    t = np.linspace(0.0, 1.0, 11)
    radius, eps = 0.22, 0.1
    for u in (40.0, 2 * eps):  # far above the scale and just above it
        spin = 0.99 * u / radius * t / 0.37  # omega R0 = 0.99 u at t = 0.37
        assert math.isclose(spin_up(t, spin, np.full(11, u), radius, 0.99, eps), 0.37)
        late = np.where(t < 0.25, eps / 2, u)  # below the scale up to t = 0.2
        assert math.isclose(spin_up(t, spin, late, radius, 0.99, eps), 0.37)
        early = np.where(t < 0.35, u, eps / 2)  # below it from t = 0.4
        assert math.isnan(spin_up(t, spin, early, radius, 0.99, eps))
    roundoff = 1e-20 * np.sin(40 * t)  # both signals round-off: they cross zero often
    assert math.isnan(spin_up(t, roundoff, roundoff[::-1], radius, 0.99, eps))


def test_a_drop_without_forward_speed_has_no_spin_up_nor_spring_back(tmp_path):
    """The shipped gear at 0 m/s forward (the start holding the axle, the airframe and the
    wheel), 3-D, over 30 ms: in contact from the first steps, and past the 10.2 ms at which
    the rule without its scale reported a spin-up from round-off (and a spring-back of
    1.7e-25 N after it)."""
    scene = small("landing_gear")
    study = scene["study"]
    study["t_end"] = 150 * study["step"]
    study["start"] = {"velocity": [0.0, 0.0, -2.675], "hold": ["axle", "airframe", "wheel"]}
    study["planar"] = False
    path, out = tmp_path / "drop.toml", tmp_path / "drop"
    path.write_text(tomli_w.dumps(scene))
    code, _, err = command("run", str(path), "--out", str(out))
    assert code == 0, err
    with open(out / "summary.csv", newline="") as stream:
        row = next(csv.DictReader(stream))
    assert float(row["contact_time"]) < study["t_end"]  # a drop onto the ground
    assert float(row["ground_vertical"]) > 0
    empty = {k: row[k] for k in ("spin_up_time", "spring_back", "spring_back_frequency")}
    assert empty == dict.fromkeys(empty, "")
