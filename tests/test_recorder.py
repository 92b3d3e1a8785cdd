"""The recorder of a time integration (``sliders.app.history.Recorder``): what it keeps and
computes, against the definitions it writes.

Sources of the asserted numbers:

* the energies are their definitions, ``v.M v / 2``, ``q.K q / 2``, and the work integrals
  the trapezoidal rule over each step of ``f . dq``, ``(M qdd + C v + K q - f) . dq`` and
  ``v.C v dt``, evaluated here step by step from the recorded states with numpy's own
  products: the recorder forms the same sums by blocks of steps, in another order, so they
  agree to round-off (``n eps`` times the sum of the terms' magnitudes per product, summed
  over the steps for the integrals);
* a step's numbers do not depend on how the steps are grouped into blocks (each is the
  same sequence of operations): the text of a recording by blocks of one step and by blocks
  of many is the same, byte for byte, as a resumed run needs;
* what a selection keeps is the full recording's cells, exactly (the same numbers written
  the same way), and a linear probe is the table cell it reads.
"""

from __future__ import annotations

import csv
import io

import numpy as np
import pytest
from test_scenes import data

from sliders.app import history
from sliders.app.history import Recorder, history_columns
from sliders.app.model import Model
from sliders.app.probes import force_probe, node_probe
from sliders.app.scene import parse_scene
from sliders.app.state_tables import Selection

EPS = np.finfo(float).eps
TABLES = ["nodes", "sliders", "internal_forces", "reactions"]


@pytest.fixture(scope="module")
def pushed():
    """The pushed body (a driven slider, damping: every energy term at work) for 40
    steps, and its states."""
    scene = data("pushed_body")
    scene["study"].update(t_end=2.0)
    model = Model(parse_scene(scene))
    dynamics = model.dynamics()
    keep = Recorder(history=["t"], every=1)  # every state
    dynamics.run(dynamics.static_state(), 2.0, 0.05, recorder=keep, progress=False)
    return model, dynamics, keep.states


def replay(dynamics, states, recorder: Recorder) -> Recorder:
    """``recorder`` fed the same states the integration gave (the load at each step's time
    asked first, as the step does)."""
    recorder.start(dynamics, states[0])
    for old, new in zip(states[:-1], states[1:], strict=True):
        dynamics.load(new.t)
        recorder.record(dynamics, new, old)
    recorder.close()
    return recorder


def test_the_energies_are_their_definitions(pushed):
    _, d, states = pushed
    table = replay(d, states, Recorder()).table()
    kinetic = [s.v @ (d.M @ s.v) / 2 for s in states]
    strain = [s.q @ (d.K @ s.q) / 2 for s in states]
    power = [s.v @ (d.C @ s.v) for s in states]
    forces = [d.load(s.t) for s in states]
    reactions = [d.constraint_forces(s) for s in states]
    work, bounds = np.zeros((len(states), 3)), np.zeros((len(states), 3))
    for k in range(1, len(states)):
        dq = states[k].q - states[k - 1].q
        terms = [
            (forces[k - 1] + forces[k]) * dq / 2,
            (reactions[k - 1] + reactions[k]) * dq / 2,
        ]
        step = [t.sum() for t in terms] + [states[k].h * (power[k - 1] + power[k]) / 2]
        work[k] = work[k - 1] + step
        size = [np.abs(t).sum() for t in terms] + [abs(step[2])]
        bounds[k] = bounds[k - 1] + d.K.shape[0] * EPS * np.array(size)
    n = d.K.shape[0]

    def bound(A, x):
        return n * EPS * np.abs(x) @ (abs(A) @ np.abs(x)) / 2

    np.testing.assert_allclose(
        table["kinetic"], kinetic, rtol=0, atol=max(bound(d.M, s.v) for s in states)
    )
    np.testing.assert_allclose(
        table["strain"], strain, rtol=0, atol=max(bound(d.K, s.q) for s in states)
    )
    for i, name in enumerate(("external_work", "constraint_work", "dissipated")):
        assert np.all(
            np.abs(table[name] - work[:, i]) <= bounds[:, i] + n * EPS * np.abs(work[:, i])
        )
    assert np.abs(table["dissipated"]).max() > 0 and np.abs(table["constraint_work"]).max() > 0


def test_blocks_of_one_step_write_the_bytes_of_blocks_of_many(pushed, monkeypatch):
    _, d, states = pushed
    probes = {"tip": node_probe(d.structure, "cantilever.end", "uy")}
    many = replay(d, states, Recorder(None, TABLES, probes))
    monkeypatch.setattr(history._Balance, "BUFFER", 1)  # one step per block
    monkeypatch.setattr(history._Records, "BLOCK", 3)
    one = replay(d, states, Recorder(None, TABLES, probes))
    assert one._balance.size == 1 and many._balance.size > len(states)
    for name in ["history", *TABLES]:
        assert one.text(name) == many.text(name), name


def test_a_streaming_recorder_writes_in_blocks_the_file_of_one_in_memory(pushed, tmp_path):
    _, d, states = pushed
    streamed = replay(d, states, Recorder(tmp_path / "streamed", TABLES, flush_rows=7))
    memory = replay(d, states, Recorder(None, TABLES))
    (tmp_path / "memory").mkdir()
    memory.write(tmp_path / "memory")
    for name in ["history", *TABLES]:
        text = (tmp_path / "streamed" / f"{name}.csv").read_bytes()
        assert text == (tmp_path / "memory" / f"{name}.csv").read_bytes(), name
    assert not list((tmp_path / "streamed").glob("*.part"))
    written = streamed._records["nodes"]  # a table's rows are dropped once written
    assert written.count == len(states) and not written.blocks and not written.pending


def read(text: str) -> list[list[str]]:
    return list(csv.reader(io.StringIO(text)))


def test_a_selection_keeps_the_full_recordings_cells(pushed):
    _, d, states = pushed
    full = replay(d, states, Recorder(None, TABLES))
    kept = ["kinetic", "push.xi", "push.lambda_y"]
    selections = {
        "nodes": Selection(("cantilever.end", "cart"), ("uy", "rz")),
        "sliders": Selection(None, ("x", "lambda_y")),
        "internal_forces": Selection(("cantilever",), ("V2", "M3")),
        "reactions": Selection(("cantilever.start",), ("fy", "mz")),
    }
    part = replay(d, states, Recorder(None, selections, history=kept))
    headers = {
        "history": ["step", "t", *kept],
        "nodes": ["step", "t", "part", "xi", "uy", "rz"],
        "sliders": ["step", "t", "slider", "x", "lambda_y"],
        "internal_forces": ["step", "t", "beam", "xi", "V2", "M3"],
        "reactions": ["step", "t", "node", "fy", "mz"],
    }
    for name, header in headers.items():
        assert list(part.headers[name]) == header
        whole = read(full.text(name))
        columns = [list(full.headers[name]).index(c) for c in header]
        rows = [[row[c] for c in columns] for row in whole]
        if name == "nodes":  # the cantilever's end (the last of its nodes by xi) and the body
            rows = [r for k, r in enumerate(rows) if k % 4 in (2, 3)]
        if name == "reactions":
            rows = [r for r in rows if r[2] == "cantilever.start"]
        assert read(part.text(name)) == rows, name


def test_history_names_and_table_selections_are_checked(pushed):
    _, d, states = pushed
    with pytest.raises(ValueError, match=r"history\[1\] = 'kinetc': no such column.*'kinetic'"):
        Recorder(None, history=["t", "kinetc"]).start(d, states[0])
    with pytest.raises(ValueError, match=r"nodes columns\[0\] = 'uyy'.*did you mean 'uy'"):
        Recorder(None, {"nodes": Selection(None, ("uyy",))}).start(d, states[0])
    with pytest.raises(ValueError, match=r"sliders items\[0\] = 'psuh'.*did you mean 'push'"):
        Recorder(None, {"sliders": Selection(("psuh",))}).start(d, states[0])
    assert "push.residual" in history_columns(d.sliders)


def test_linear_probes_are_the_cells_they_read(pushed):
    model, d, states = pushed
    probes = {
        "tip": node_probe(d.structure, "cantilever.end", "uy"),
        "shear": force_probe(d.structure, "cantilever", 0.79, "V2"),
    }
    recorder = replay(d, states, Recorder(None, ["nodes", "internal_forces"], probes))
    table = recorder.table()
    nodes = read(recorder.text("nodes"))
    tip = [float(r[8]) for r in nodes if r[2] == "cantilever" and float(r[3]) == 1.0]
    np.testing.assert_array_equal(table["tip"], tip)
    beam = d.structure.beams[0]
    point = np.argmin(np.abs(beam.recovery_abscissae - 0.79))
    forces = read(recorder.text("internal_forces"))
    shear = [float(r[5]) for r in forces if float(r[3]) == beam.recovery_abscissae[point]]
    # one product of the same row with q: the same sum, in the same order
    np.testing.assert_array_equal(table["shear"], shear)


def test_the_carry_of_a_past_step_is_the_one_taken_at_that_step(pushed):
    """What a checkpoint saves of step ``k``, asked for once later steps are recorded (its
    state given), is what the recorder carried when ``k`` was its last step: the same
    arrays, bit for bit (the same products, on a block of one step)."""
    _, d, states = pushed
    later, now = Recorder(), Recorder()
    later.start(d, states[0])
    now.start(d, states[0])
    taken = []
    for old, new in zip(states[:-1], states[1:], strict=True):
        for recorder in (later, now):
            recorder.record(d, new, old)
        taken.append(now.carry())
    for k in (0, 7, len(taken) - 1):
        asked = later.carry(states[k + 1], k + 2)
        assert asked.keys() == taken[k].keys()
        for key, value in taken[k].items():
            assert np.array_equal(asked[key], value, equal_nan=True), (k, key)


def test_rows_copied_from_a_checkpoint_are_the_rows_formatted(pushed, tmp_path):
    """A recorder writing with a file of its first rows (a checkpoint's, header included)
    copies them and formats the rest: the bytes of the file it writes alone."""
    _, d, states = pushed
    recorder = replay(d, states, Recorder(tables=TABLES))
    (tmp_path / "alone").mkdir()
    recorder.write(tmp_path / "alone")
    written = {}
    for name, header in recorder.headers.items():
        rows = recorder.count(name) // 3
        head = io.StringIO(newline="")
        csv.writer(head).writerow(header)
        data = (head.getvalue() + recorder.text(name, 0, rows)).encode()
        (tmp_path / f"{name}.part").write_bytes(data + b"a torn append")
        written[name] = (tmp_path / f"{name}.part", rows, len(data))
    (tmp_path / "copied").mkdir()
    recorder.write(tmp_path / "copied", written)
    for name in recorder.headers:
        copied = (tmp_path / "copied" / f"{name}.csv").read_bytes()
        assert copied == (tmp_path / "alone" / f"{name}.csv").read_bytes(), name
