"""Campaign files: one scene over many cases (``docs/campaigns.md``).

A campaign file (TOML) names a scene (``scene``, relative to the campaign file), the keys it
varies (``[[axis]]``, each a key path of the scene as its errors print it:
:mod:`sliders.app.scene_keys`) and the scalar results each case reports (``[[result]]``).
The cases are the product of the axes' ``values`` (``combine = "product"``, the default),
their ``i``-th values together (``combine = "zip"``: a list of cases), or a seeded random
sample (``[sample]``: each axis draws uniformly from its ``range`` or its ``values``).
:func:`read_campaign` validates the file (every problem at its key path, one
:class:`~sliders.app.errors.SceneError`), reads the scene and checks that every key leads into
it; :meth:`Campaign.cases` resolves each case's scene.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, StrictInt, ValidationError, model_validator

from sliders.app.errors import Problem, Problems, SceneError, schema_problems
from sliders.app.scene_keys import KeyPathError, check_key, with_values
from sliders.app.schema import Name, Names, Table, Text

#: A value an axis gives a key: a number, a string, a boolean, or an array of them.
Value = Any


class AxisSpec(Table):
    """``[[axis]]``: the scene ``key`` (or the ``keys`` varied together, each value then a
    list of one value per key) and its ``values``, or the ``range = [low, high]`` a random
    sample draws from (integers when both ends are)."""

    key: Text | None = None
    keys: Annotated[tuple[Text, ...], Field(min_length=1)] | None = None
    values: Annotated[tuple[Value, ...], Field(min_length=1)] | None = None
    range: tuple[StrictInt, StrictInt] | tuple[float, float] | None = None

    @model_validator(mode="after")
    def _one_way(self) -> AxisSpec:
        if (self.key is None) == (self.keys is None):
            raise ValueError("give key (one scene key) or keys (several, varied together)")
        if (self.values is None) == (self.range is None):
            raise ValueError("give values, or a range for a random sample")
        if self.range is not None and not self.range[0] < self.range[1]:
            raise ValueError(f"range {list(self.range)}: needs low < high")
        if self.keys is not None and self.values is not None:
            for value in self.values:
                if not isinstance(value, list | tuple) or len(value) != len(self.keys):
                    raise ValueError(
                        f"value {value!r}: with {len(self.keys)} keys, each value is a list "
                        f"of {len(self.keys)}"
                    )
        if self.keys is not None and self.range is not None:
            raise ValueError("a range varies one key: give key, not keys")
        return self

    @property
    def names(self) -> tuple[str, ...]:
        """The keys this axis sets, in order."""
        return (self.key,) if self.key is not None else tuple(self.keys or ())


class ResultSpec(Table):
    """``[[result]]``: a scalar of each case, reduced from ``column`` of the run's ``table``
    (``history`` for a dynamic study; ``samples``, ``nodes``, ``sliders``,
    ``internal_forces``, ``reactions``, the rows ``where`` selects, for any study):

    ``max``, ``min``, ``absmax`` (the signed value of largest magnitude)
        the recorded row where ``column`` peaks: the value, its time (``t``, or a sweep's
        ``value``) as ``NAME.t``, and the ``concurrent`` columns of that row as
        ``NAME.COLUMN``;
    ``last``
        the last row's value (and ``concurrent`` columns);
    ``efficiency``
        the work of ``column`` (a force) over ``over`` (its displacement) up to the row where
        ``over`` peaks, divided by the peak force times the peak displacement (a shock
        absorber's efficiency; 1 for a constant force), trapezoidal over the rows.

    ``per = "weight"`` divides the value (not its concurrent columns) by the case's weight,
    its total mass (bodies and beams) times ``|study.gravity|``: a load as a load factor.
    """

    name: Name
    column: Text
    reduce: Literal["max", "min", "absmax", "last", "efficiency"] = "absmax"
    table: Text = "history"
    over: Text | None = None
    concurrent: Names = ()
    where: dict[str, str | float] | None = None
    per: Literal["weight"] | None = None

    @model_validator(mode="after")
    def _over(self) -> ResultSpec:
        if (self.reduce == "efficiency") != (self.over is not None):
            raise ValueError("over (the displacement column) goes with reduce = 'efficiency' only")
        return self


class ReportSpec(Table):
    """``[report]``: the campaign's picture, ``report.png``: each result named in ``plot``
    (a panel each) against the values of the axis key ``against``, one line per combination
    of the other axes' values, coloured by the values of the axis key ``colour`` (optional;
    :mod:`sliders.app.campaign_report`)."""

    plot: Annotated[tuple[Text, ...], Field(min_length=1)]
    against: Text
    colour: Text | None = None


class SampleSpec(Table):
    """``[sample]``: ``size`` cases drawn with the random generator seeded by ``seed``."""

    size: Annotated[int, Field(gt=0)]
    seed: int


class CampaignSpec(Table):
    """A campaign file (module docstring)."""

    title: Text = ""
    scene: Text
    combine: Literal["product", "zip"] = "product"
    sample: SampleSpec | None = None
    axis: Annotated[tuple[AxisSpec, ...], Field(min_length=1)]
    result: tuple[ResultSpec, ...] = ()
    report: ReportSpec | None = None

    @model_validator(mode="after")
    def _report(self) -> CampaignSpec:
        if self.report is None:
            return self
        results = [r.name for r in self.result]
        for name in self.report.plot:
            if name not in results:
                raise ValueError(f"report: plot names {name!r}, not a result ({results})")
        keys = [k for a in self.axis for k in a.names]
        for what in ("against", "colour"):
            key = getattr(self.report, what)
            if key is not None and key not in keys:
                raise ValueError(f"report: {what} = {key!r} is not an axis key ({keys})")
        return self

    @model_validator(mode="after")
    def _cases(self) -> CampaignSpec:
        if self.sample is None:
            if any(a.range is not None for a in self.axis):
                raise ValueError("an axis with a range needs [sample] (size, seed)")
            if self.combine == "zip" and len({len(a.values or ()) for a in self.axis}) > 1:
                counts = [len(a.values or ()) for a in self.axis]
                raise ValueError(f"combine = 'zip' needs axes of one length, not {counts}")
        names = [k for a in self.axis for k in a.names]
        twice = sorted({k for k in names if names.count(k) > 1})
        if twice:
            raise ValueError(f"keys varied by more than one axis: {', '.join(twice)}")
        return self


@dataclass(frozen=True)
class Case:
    """One case: its ``index``, the ``values`` of the keys (key path to value), its resolved
    ``scene`` (the scene document with them set) and its ``key`` (:func:`case_key`)."""

    index: int
    values: dict[str, Value]
    scene: dict
    key: str


@dataclass(frozen=True)
class Campaign:
    """A validated campaign: its ``spec``, the ``scene`` document it varies, the folder
    ``base`` the scene's relative paths start from and the campaign's ``source`` name."""

    spec: CampaignSpec
    scene: dict
    base: Path
    source: str = "campaign"

    @property
    def columns(self) -> tuple[str, ...]:
        """The key paths the cases set: a column of the cases table each."""
        return tuple(k for a in self.spec.axis for k in a.names)

    def values(self) -> list[dict[str, Value]]:
        """Each case's values, key path to value, in case order."""
        spec = self.spec
        if spec.sample is not None:
            rng = np.random.default_rng(spec.sample.seed)
            draws = [_draw(a, rng, spec.sample.size) for a in spec.axis]
            rows = list(zip(*draws, strict=True))
        elif spec.combine == "zip":
            rows = list(zip(*(a.values or () for a in spec.axis), strict=True))
        else:
            rows = list(itertools.product(*(a.values or () for a in spec.axis)))
        cases = []
        for row in rows:
            values: dict[str, Value] = {}
            for axis, value in zip(spec.axis, row, strict=True):
                given = value if axis.keys is not None else (value,)
                values.update(zip(axis.names, given, strict=True))
            cases.append(values)
        return cases

    def cases(self) -> list[Case]:
        """Every case with its resolved scene and key."""
        found = []
        for index, values in enumerate(self.values()):
            scene = with_values(self.scene, values)
            found.append(Case(index, values, scene, case_key(scene, self.base, self.spec.result)))
        return found


def _draw(axis: AxisSpec, rng: np.random.Generator, size: int) -> list[Value]:
    """``size`` values of ``axis``: uniform in its range (integers when both ends are), or
    drawn from its values."""
    if axis.values is not None:
        return [axis.values[int(i)] for i in rng.integers(0, len(axis.values), size)]
    assert axis.range is not None  # AxisSpec has one or the other
    low, high = axis.range
    if isinstance(low, int) and isinstance(high, int):
        return [int(v) for v in rng.integers(low, high, size, endpoint=True)]
    return [float(v) for v in rng.uniform(low, high, size)]


@cache
def code_version() -> str:
    """A digest of the library's source (every ``.py`` file of ``fvbeam`` and ``sliders``):
    a case computed by other code is not a finished case."""
    import fvbeam
    import sliders

    digest = hashlib.sha256()
    for package in (fvbeam, sliders):
        root = Path(str(package.__file__)).parent
        for path in sorted(root.rglob("*.py")):
            digest.update(str(path.relative_to(root.parent)).encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def case_key(scene: dict, base: Path, results: tuple[ResultSpec, ...]) -> str:
    """The key of a case: a digest of its resolved scene, the folder its relative paths start
    from, the results asked of it and :func:`code_version`."""
    text = json.dumps(
        [scene, str(base), [r.model_dump() for r in results], code_version()],
        sort_keys=True,
        default=repr,
    )
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def parse_campaign(data: dict, base: Path, source: str = "campaign") -> Campaign:
    """Validate a campaign document (the dict ``tomllib`` reads), read its scene (relative to
    ``base``, the campaign file's folder) and check every axis key against the scene.

    Raises
    ------
    SceneError
        Every problem of the campaign (at its key path: ``axis[1].key``), or of reading its
        scene, in one message.
    """
    try:
        spec = CampaignSpec.model_validate(data)
    except ValidationError as exc:
        raise SceneError(source, schema_problems(exc, CampaignSpec), "invalid campaign") from None
    path = base / spec.scene
    try:
        scene = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        message = exc.strerror if isinstance(exc, OSError) else str(exc)
        raise SceneError(
            source,
            [Problem("scene", f"cannot read {path}: {message}", spec.scene)],
            "invalid campaign",
        ) from None
    problems = Problems()
    for i, axis in enumerate(spec.axis):
        for j, key in enumerate(axis.names):
            where = f"axis[{i}].key" if axis.key is not None else f"axis[{i}].keys[{j}]"
            try:
                check_key(scene, key)
            except KeyPathError as exc:
                problems.add(where, str(exc))
    problems.raise_if_any(source, "invalid campaign")
    return Campaign(spec, scene, path.parent, source)


def read_campaign(path: str | Path) -> Campaign:
    """Read and validate the campaign file ``path`` (:func:`parse_campaign`)."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise SceneError(
            str(path), [Problem("", f"cannot read the file: {exc.strerror}")], "invalid campaign"
        ) from None
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise SceneError(
            str(path), [Problem("", f"not valid TOML: {exc}")], "invalid campaign"
        ) from None
    return parse_campaign(data, path.parent, str(path))
