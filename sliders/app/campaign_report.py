"""A campaign's picture: its results over the matrix of cases (``[report]``,
:class:`sliders.app.campaign_spec.ReportSpec`).

:func:`write_report` draws ``report.png`` from the cases table: a panel per result named in
``plot``, the result of each finished case against the values of the axis key ``against``,
one line per combination of the other axes' values (each line one column of the matrix,
swept along ``against`` and the keys its axis varies with it), coloured by the values of
the axis key ``colour`` when given.  The landing-gear campaign draws its peak vertical,
spin-up and spring-back loads and its load factor against the sink speed, coloured by the
tyre's friction peak (``docs/campaigns.md``).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import TYPE_CHECKING

from fvbeam.io import write_atomic
from sliders.app.campaign_spec import Campaign

if TYPE_CHECKING:
    import pandas as pd

#: The picture's name in the campaign's output directory.
REPORT = "report.png"


def write_report(table: pd.DataFrame, campaign: Campaign, out: Path) -> Path | None:
    """Draw the ``[report]`` of ``campaign`` from its cases ``table`` (module docstring) as
    ``out/report.png`` (atomically); its path, or None without matplotlib (the ``plot``
    extra), a ``[report]`` or a finished case."""
    spec = campaign.spec.report
    if spec is None or importlib.util.find_spec("matplotlib") is None:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = table[table["status"] == "ok"]
    if ok.empty:
        return None
    others = [k for a in campaign.spec.axis if spec.against not in a.names for k in a.names]
    colours = [] if spec.colour is None else sorted(ok[spec.colour].unique(), key=str)
    groups = list(ok.groupby(others, sort=True, dropna=False)) if others else [((), ok)]
    fig, axes = plt.subplots(
        len(spec.plot), 1, figsize=(7.5, 2.6 * len(spec.plot) + 0.6), sharex=True, squeeze=False
    )
    for ax, name in zip(axes[:, 0], spec.plot, strict=True):
        for _, rows in groups:
            rows = rows.sort_values(spec.against, kind="stable")
            colour = "C0"
            if spec.colour is not None:
                colour = f"C{colours.index(rows[spec.colour].iloc[0]) % 10}"
            ax.plot(rows[spec.against], rows[name], marker="o", ms=3, lw=0.8, color=colour)
        ax.set_ylabel(name)
        ax.grid(True, alpha=0.3)
    if spec.colour is not None:
        handles = [
            plt.Line2D([], [], color=f"C{i % 10}", marker="o", label=f"{spec.colour} = {v}")
            for i, v in enumerate(colours)
        ]
        axes[0, 0].legend(handles=handles, fontsize="small")
    axes[-1, 0].set_xlabel(spec.against)
    title = campaign.spec.title or "campaign"
    fig.suptitle(f"{title}: {len(ok)} cases, a line per combination of the other axes")
    path = out / REPORT
    try:
        write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=120, bbox_inches="tight"))
    finally:
        plt.close(fig)
    return path
