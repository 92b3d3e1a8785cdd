"""Campaigns: one scene run over many cases on Dask, results in one tidy table.

:func:`run_case` is a pure function of a case's resolved scene: it validates and builds it,
runs its study as ``fvslider run`` does (:func:`sliders.app.run.run`) and writes its tables
with the same writers (:func:`sliders.app.tables.write_results`,
:func:`sliders.app.run_dynamic.write_dynamic`), then reduces them to the campaign's results
(:class:`sliders.app.campaign_spec.ResultSpec`).  A case that fails (an invalid value, a
solve that does not converge, anything raised) is a row with ``status = "failed"`` and its
message, never the campaign's end.

:func:`run_campaign` sends the cases to a ``dask.distributed`` cluster (a local one of
``workers`` processes by default, or the scheduler at ``scheduler``), and as each case
finishes writes ``cases.csv`` and ``cases.parquet`` atomically into the output directory: one
row per case, ``case, key``, a column per varied key, ``status, seconds, message``, then the
results.  ``resume`` keeps the rows of the directory's table whose ``key`` (the resolved
scene, the results asked for and the code: :func:`sliders.app.campaign_spec.case_key`) is
still a case, and runs only the others.  A local cluster's workers run with one BLAS and one
numba thread each (:data:`PINNED`, :func:`pin_numba`).
"""

from __future__ import annotations

import logging
import math
import os
import shutil
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from fvbeam.io import OUTPUT_MARKER, check_replaceable, write_atomic
from sliders.app.campaign_spec import Campaign, Case, ResultSpec

if TYPE_CHECKING:
    import pandas as pd

    from sliders.app.model import Model

#: The environment of a local cluster's workers: one BLAS thread each, so that ``workers``
#: cases use ``workers`` cores.  Numba's threads are pinned at run time on every worker
#: (:func:`pin_numba`): ``NUMBA_NUM_THREADS`` in the environment would change the kernels'
#: cache keys and recompile them all in every worker.
PINNED = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
#: The columns of the cases table before the varied keys, and after them.
HEAD = ("case", "key")
STATUS = ("status", "seconds", "message")
TABLES = ("cases.csv", "cases.parquet")


@dataclass
class Outcome:
    """What :func:`run_campaign` did: the cases ``table`` (one row per finished case),
    how many cases were ``run`` now and ``skipped`` (finished before, ``resume``), how many
    ``failed`` in all, ``interrupted`` by Ctrl-C, and the wall-clock ``seconds``."""

    table: pd.DataFrame
    run: int = 0
    skipped: int = 0
    failed: int = 0
    interrupted: bool = False
    seconds: float = 0.0
    lost: list[str] = field(default_factory=list)
    #: The report's picture (``[report]``), None when not drawn.
    report: Path | None = None


def reduce(frame: pd.DataFrame, spec: ResultSpec, weight: float | None = None) -> dict[str, Any]:
    """The result ``spec`` of one run's table ``frame`` (:class:`ResultSpec`): the columns
    ``NAME``, ``NAME.t`` and ``NAME.COLUMN`` for each concurrent column; with ``per =
    "weight"`` the value divided by the case's ``weight`` (:func:`weight_of`)."""
    rows = frame
    for column, wanted in (spec.where or {}).items():
        rows = rows[rows[column] == wanted]
    missing = [c for c in (spec.column, spec.over, *spec.concurrent) if c and c not in frame]
    if missing:
        known = ", ".join(map(str, frame.columns))
        raise ValueError(f"result {spec.name}: no column {missing[0]!r} in {spec.table} ({known})")
    if rows.empty:
        raise ValueError(f"result {spec.name}: no row of {spec.table} is {spec.where}")
    y = rows[spec.column].to_numpy(dtype=float)
    time_column = "t" if "t" in rows else "value"
    if spec.reduce == "efficiency":
        assert spec.over is not None  # ResultSpec requires it
        x = rows[spec.over].to_numpy(dtype=float)
        at = int(np.argmax(x))
        work = float(np.sum(0.5 * (y[1 : at + 1] + y[:at]) * np.diff(x[: at + 1])))
        peak = float(np.max(y[: at + 1])) * float(x[at])
        value = work / peak if peak > 0 else math.nan
    else:
        at = {
            "max": lambda: int(np.argmax(y)),
            "min": lambda: int(np.argmin(y)),
            "absmax": lambda: int(np.argmax(np.abs(y))),
            "last": lambda: len(y) - 1,
        }[spec.reduce]()
        value = float(y[at])
    if spec.per == "weight":
        if weight is None or not weight > 0:
            raise ValueError(f"result {spec.name}: per = 'weight' needs a weight, got {weight}")
        value /= weight
    found: dict[str, Any] = {spec.name: value}
    if time_column in rows:
        found[f"{spec.name}.t"] = rows[time_column].iloc[at]
    for column in spec.concurrent:
        found[f"{spec.name}.{column}"] = rows[column].iloc[at]
    return found


def weight_of(model: Model) -> float:
    """The weight of a scene: its bodies' and beams' mass (``mass_per_length`` times
    length) times ``|study.gravity|``; ``ValueError`` without gravity."""
    gravity = model.scene.study.gravity
    if gravity is None:
        raise ValueError("per = 'weight' needs study.gravity")
    structure = model.structure
    mass = sum(body.mass for body in structure.bodies) + sum(
        beam.section.mass_per_length * beam.mesh.length for beam in structure.beams
    )
    return float(mass * np.linalg.norm(gravity))


def run_case(case: Case, campaign: Campaign, keep: str | Path | None = None) -> dict[str, Any]:
    """Run one case (module docstring) and return its row of the cases table; ``keep``: the
    directory to write the run's tables into (as ``fvslider run --out``), else a temporary one
    that is removed."""
    import pandas as pd

    from sliders.app.model import Model
    from sliders.app.run import Results, run
    from sliders.app.run_dynamic import DynamicRun, write_dynamic
    from sliders.app.scene import load_scene
    from sliders.app.tables import write_results

    row: dict[str, Any] = {"case": case.index, "key": case.key, **case.values}
    clock = time.perf_counter()
    with _run_directory(keep) as out:
        try:
            source = f"case {case.index}"
            model = Model(load_scene(case.scene, base=campaign.base, source=source), source)
            outcome = run(model, progress=False)
            if isinstance(outcome, DynamicRun):
                write_dynamic(outcome, out)
                error = outcome.error
            else:
                assert isinstance(outcome, Results)
                write_results(outcome, out)
                error = outcome.failures[0].error if outcome.failures else None
            if error is not None:
                raise ValueError(error)
            frames: dict[str, pd.DataFrame] = {}
            specs = campaign.spec.result
            weight = weight_of(model) if any(r.per == "weight" for r in specs) else None
            for spec in specs:
                if spec.table not in frames:
                    path = out / f"{spec.table}.csv"
                    if not path.is_file():
                        raise ValueError(f"result {spec.name}: the run wrote no {spec.table}.csv")
                    frames[spec.table] = pd.read_csv(path)
                row.update(reduce(frames[spec.table], spec, weight))
            row.update(status="ok", message=None)
        except Exception as exc:
            message = str(exc) if isinstance(exc, ValueError) else f"{type(exc).__name__}: {exc}"
            row.update(status="failed", message=message)
    row["seconds"] = time.perf_counter() - clock
    return row


@contextmanager
def _run_directory(keep: str | Path | None) -> Iterator[Path]:
    if keep is not None:
        yield Path(keep)
        return
    with tempfile.TemporaryDirectory(prefix="fvslider-case-") as tmp:
        yield Path(tmp) / "run"


def _ordered(table: pd.DataFrame, campaign: Campaign) -> pd.DataFrame:
    first = [*HEAD, *campaign.columns, *STATUS]
    rest = [c for c in table.columns if c not in first]
    return table.reindex(columns=first + rest).sort_values("case", kind="stable")


def write_table(rows: list[dict[str, Any]], campaign: Campaign, out: Path) -> pd.DataFrame:
    """``rows`` as the cases table, written atomically to ``out/cases.csv`` and
    ``out/cases.parquet``; returns it."""
    import pandas as pd

    table = _ordered(pd.DataFrame(rows), campaign).reset_index(drop=True)
    for column in table.columns:
        if table[column].dtype == object:  # mixed or missing values: text in Parquet
            table[column] = table[column].map(lambda v: None if _missing(v) else str(v))
    write_atomic(out / "cases.csv", lambda p: table.to_csv(p, index=False))
    write_atomic(out / "cases.parquet", lambda p: table.to_parquet(p, index=False))
    return table


def _missing(value: Any) -> bool:
    return value is None or (isinstance(value, float) and math.isnan(value))


def finished(out: Path) -> list[dict[str, Any]]:
    """The rows of the cases table in ``out`` (none if there is none)."""
    import pandas as pd

    path = out / "cases.parquet"
    if not path.is_file():
        return []
    return pd.read_parquet(path).to_dict("records")


def prepare(out: Path, resume: bool) -> None:
    """Make ``out`` ready: with ``resume``, keep it (it must be a directory this program
    wrote, or absent); else empty it (absent, empty, or written by this program:
    :func:`fvbeam.io.check_replaceable`)."""
    check_replaceable(out, OUTPUT_MARKER)
    if out.exists() and not resume:
        shutil.rmtree(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / OUTPUT_MARKER).write_text(
        "written by fvslider campaign; the whole directory is replaced on the next run\n"
    )


@contextmanager
def local_client(workers: int) -> Iterator[Any]:
    """A client of a new local cluster of ``workers`` processes, one thread each, their BLAS
    and numba pinned to one thread (:data:`PINNED`); closed on exit."""
    from distributed import Client, LocalCluster

    saved = {name: os.environ.get(name) for name in PINNED}
    os.environ.update(PINNED)  # the workers' processes inherit it
    try:
        cluster = LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=logging.ERROR,
        )
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
    try:
        with Client(cluster) as client:
            yield client
    finally:
        cluster.close()


def run_campaign(
    campaign: Campaign,
    out: str | Path,
    workers: int = 2,
    scheduler: str | None = None,
    resume: bool = False,
    keep: bool = False,
    progress: bool = True,
) -> Outcome:
    """Run every case of ``campaign`` not finished yet, writing the cases table into ``out``
    as they finish (module docstring).

    Parameters
    ----------
    campaign
        The validated campaign (:func:`sliders.app.campaign_spec.read_campaign`).
    out
        The output directory: ``cases.csv``, ``cases.parquet`` (and, with ``keep``,
        ``runs/case_NNNNNN/``, each as ``fvslider run --out`` writes it).
    workers
        The local cluster's size (ignored with ``scheduler``); 0 runs the cases one after
        the other in this process, without Dask.
    scheduler
        The address of a running Dask scheduler to send the cases to.
    resume
        Keep the finished cases of ``out`` and run the others.
    progress
        A progress bar of cases (tqdm, on a terminal).
    """
    from tqdm import tqdm

    out = Path(out)
    prepare(out, resume)
    clock = time.perf_counter()
    cases = campaign.cases()
    keys = {c.key for c in cases}
    rows = [r for r in finished(out) if r["key"] in keys] if resume else []
    done = {r["key"] for r in rows}
    todo = [c for c in cases if c.key not in done]
    outcome = Outcome(write_table(rows, campaign, out) if rows else _empty(), skipped=len(rows))
    bar = tqdm(
        total=len(cases),
        initial=len(rows),
        desc=campaign.spec.title or "campaign",
        unit="case",
        disable=not progress or None,
    )

    def keep_dir(case: Case) -> Path | None:
        return out / "runs" / f"case_{case.index:06d}" if keep else None

    def finish(row: dict[str, Any]) -> None:
        rows.append(row)
        outcome.run += 1
        outcome.table = write_table(rows, campaign, out)
        bar.update()

    try:
        if not todo:
            pass
        elif scheduler is None and workers == 0:
            for case in todo:
                finish(run_case(case, campaign, keep_dir(case)))
        else:
            _distributed(todo, campaign, keep_dir, finish, workers, scheduler, outcome)
    except KeyboardInterrupt:
        outcome.interrupted = True
    finally:
        bar.close()
    if campaign.spec.report is not None and not outcome.table.empty:
        from sliders.app.campaign_report import write_report

        outcome.report = write_report(outcome.table, campaign, out)
    outcome.failed = sum(r["status"] != "ok" for r in rows)
    outcome.seconds = time.perf_counter() - clock
    return outcome


def pin_numba() -> int:
    """Let numba's parallel kernels use one thread in this process; returns the count."""
    import numba

    numba.set_num_threads(1)
    return int(numba.get_num_threads())


def _distributed(todo, campaign, keep_dir, finish, workers, scheduler, outcome) -> None:
    """Send ``todo`` to the cluster and ``finish`` each row as it comes back; a case lost with
    its workers (after Dask's retries) is not a row: ``resume`` runs it again."""
    from distributed import Client, as_completed

    with Client(scheduler) if scheduler is not None else local_client(workers) as client:
        client.run(pin_numba)
        shared = client.scatter(campaign, broadcast=True)
        futures = {
            client.submit(
                run_case, case, shared, keep_dir(case), key=f"case-{case.index}-{case.key}"
            ): case
            for case in todo
        }
        try:
            for future in as_completed(futures):
                if future.status == "finished":
                    finish(future.result())
                else:
                    case = futures[future]
                    outcome.lost.append(f"case {case.index}: {future.exception()}")
        finally:
            client.cancel(list(futures))


def _empty() -> pd.DataFrame:
    import pandas as pd

    return pd.DataFrame()


def command(
    path: Path, out: Path, workers: int, scheduler: str | None, resume: bool, keep: bool
) -> int:
    """``fvslider campaign``: run the campaign file ``path`` into ``out`` (:func:`run_campaign`)
    and say what happened; the exit code: 0 every case ok, 1 a case failed, 2 an invalid
    campaign or output directory, 130 interrupted."""
    import sys

    from sliders.app.campaign_spec import read_campaign

    if workers < 0:
        print(f"fvslider: --workers {workers}: give 0 (in this process) or more", file=sys.stderr)
        return 2
    campaign = read_campaign(path)
    outcome = run_campaign(campaign, out, workers, scheduler, resume, keep)
    total = len(outcome.table)
    print(
        f"{outcome.run} cases run, {outcome.skipped} finished before, {outcome.failed} failed "
        f"({total} in the table) in {outcome.seconds:.1f} s, written to {out}"
    )
    if outcome.failed:
        table = outcome.table
        for _, row in table[table["status"] != "ok"].head(5).iterrows():
            print(f"  case {row['case']} failed: {row['message']}", file=sys.stderr)
    if outcome.report is not None:
        print(f"report: {outcome.report}")
    for lost in outcome.lost:
        print(f"  {lost} (lost with its worker: --resume runs it again)", file=sys.stderr)
    if outcome.interrupted:
        print("interrupted: the finished cases are written; --resume goes on", file=sys.stderr)
        return 130
    return 1 if outcome.failed or outcome.lost else 0
