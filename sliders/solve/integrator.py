"""The generalized-alpha scheme for index-3 constrained mechanics, and the integrator state.

Chung & Hulbert (1993) generalized-alpha, in the form of Arnold & Bruels (2007, Multibody
Syst. Dyn. 18:185) for index-3 DAEs: equilibrium *and* constraints are enforced at
``t_{n+1}``, with an acceleration-like variable ``a`` (not the acceleration ``qdd``)::

    (1 - alpha_m) a_{n+1} + alpha_m a_n = (1 - alpha_f) qdd_{n+1} + alpha_f qdd_n
    q_{n+1} = q_n + h v_n + h^2 (1/2 - beta) a_n + h^2 beta a_{n+1}
    v_{n+1} = v_n + h (1 - gamma) a_n + h gamma a_{n+1}

    M qdd_{n+1} + C v_{n+1} + K q_{n+1} + r(q_{n+1}, y_{n+1}) = f(t_{n+1})
    g(q_{n+1}, y_{n+1}, t_{n+1}) = 0

with, for a spectral radius at infinity ``rho_inf`` in [0, 1],
``alpha_m = (2 rho - 1)/(rho + 1)``, ``alpha_f = rho/(rho + 1)``,
``gamma = 1/2 + alpha_f - alpha_m``, ``beta = (gamma + 1/2)^2 / 4``: second order, unconditionally
stable on linear problems, no dissipation at ``rho_inf = 1`` (the trapezoidal rule) and
asymptotic annihilation at 0.  Why this one rather than the reference implementation's
multistep family (MBDyn's): it is one-step, so a step
size change or a restart needs no history and no start-up step (MBDyn's first step is
Crank-Nicolson), and its Newton matrix ``M + c_v C + c_q K`` keeps the shape of the static one.

Per step, ``qdd_{n+1}`` and ``v_{n+1}`` are affine in ``q_{n+1}`` (:meth:`GeneralizedAlpha.
predict`), so the step is a static problem on the operator ``K_eff = K + beta' M + gamma' C``
(``beta' = (1 - alpha_m) / ((1 - alpha_f) beta h^2)``, ``gamma' = gamma / (beta h)``).  For
small ``h`` the force equations grow like ``h^-2`` against constraints of order one; they
are scaled by ``s = 1 / beta'`` and the multipliers by the same factor (Bottasso, Bauchau &
Cardona 2007, SIAM J. Sci. Comput. 29:397), so the Newton matrix is
``M + (gamma'/beta') C + s K`` bordered by the constraints, with a condition number
independent of ``h``.
"""

from __future__ import annotations

import zipfile
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import numpy.lib.format as npy

from fvbeam.io import write_atomic


@dataclass(frozen=True)
class GeneralizedAlpha:
    """The scheme's constants for a spectral radius at infinity ``rho_inf`` in [0, 1]."""

    rho_inf: float = 0.8

    def __post_init__(self) -> None:
        rho = float(self.rho_inf)
        if not 0.0 <= rho <= 1.0:
            raise ValueError(f"rho_inf must lie in [0, 1], got {self.rho_inf!r}")
        object.__setattr__(self, "rho_inf", rho)

    @property
    def alpha_m(self) -> float:
        return (2 * self.rho_inf - 1) / (self.rho_inf + 1)

    @property
    def alpha_f(self) -> float:
        return self.rho_inf / (self.rho_inf + 1)

    @property
    def gamma(self) -> float:
        return 0.5 + self.alpha_f - self.alpha_m

    @property
    def beta(self) -> float:
        return (self.gamma + 0.5) ** 2 / 4

    def rates(self, h: float) -> tuple[float, float]:
        """``beta' = d qdd / d q`` and ``gamma' = d v / d q`` of a step ``h``."""
        return (
            (1 - self.alpha_m) / ((1 - self.alpha_f) * self.beta * h * h),
            self.gamma / (self.beta * h),
        )

    def predict(self, state: "State", h: float) -> "Prediction":
        """The known parts of a step ``h`` from ``state``: ``q_hat``, ``v_hat``, ``qdd_hat``
        such that ``q_{n+1} = q_hat + beta h^2 a_{n+1}``, ``v_{n+1} = v_hat + gamma'
        (q_{n+1} - q_hat)``, ``qdd_{n+1} = qdd_hat + beta' (q_{n+1} - q_hat)``."""
        beta, gamma = self.beta, self.gamma
        q_hat = state.q + h * state.v + h * h * (0.5 - beta) * state.a
        v_hat = state.v + h * (1 - gamma) * state.a
        qdd_hat = (self.alpha_m * state.a - self.alpha_f * state.qdd) / (1 - self.alpha_f)
        return Prediction(h, q_hat, v_hat, qdd_hat, *self.rates(h))

    def local_error(self, state: "State", new: "State") -> np.ndarray:
        """Estimate of the local displacement error of the step from ``state`` to ``new``:
        ``h^2 |beta - 1/6| (qdd_{n+1} - qdd_n)``, the leading Taylor term the scheme misses
        (Zienkiewicz & Xie 1991, for Newmark; the alpha shift leaves the order unchanged)."""
        h = new.t - state.t
        return h * h * abs(self.beta - 1.0 / 6.0) * (new.qdd - state.qdd)


@dataclass(frozen=True)
class Prediction:
    """What a step of size ``h`` knows before it solves (:meth:`GeneralizedAlpha.predict`)."""

    h: float
    q_hat: np.ndarray
    v_hat: np.ndarray
    qdd_hat: np.ndarray
    beta_rate: float
    gamma_rate: float

    def complete(
        self, t: float, q: np.ndarray, unknowns: list[np.ndarray], beta: float, iterations: int
    ) -> "State":
        """The state at ``t`` once ``q_{n+1}`` and the joint unknowns are known."""
        dq = q - self.q_hat
        return State(
            t,
            q,
            self.v_hat + self.gamma_rate * dq,
            dq / (beta * self.h**2),
            self.qdd_hat + self.beta_rate * dq,
            unknowns,
            self.h,
            iterations,
        )


@dataclass
class State:
    """Where the integration stands: time ``t``, displacements ``q``, velocities ``v``, the
    scheme's acceleration-like variable ``a`` and the accelerations ``qdd`` (all global dofs),
    the sliders' unknowns (physical multipliers), the last step ``h``, its Newton iterations
    and the joints' constraint violations it left (optional)."""

    t: float
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    qdd: np.ndarray
    unknowns: list[np.ndarray] = field(default_factory=list)
    h: float = 0.0
    iterations: int = 0
    #: Each slider's largest constraint violation, where the step that reached the state
    #: computed it (:meth:`sliders.solve.dynamics.Dynamics.joint_residuals`); not saved.
    violations: np.ndarray | None = None

    def save(self, path: str | Path) -> None:
        """Write the state to ``path`` (``.npz``, atomically) for a restart."""

        def write(tmp: Path) -> None:
            with open(tmp, "wb") as stream:
                np.savez(
                    stream,
                    t=np.array(self.t),
                    q=self.q,
                    v=self.v,
                    a=self.a,
                    qdd=self.qdd,
                    h=np.array(self.h),
                    sizes=np.array([len(y) for y in self.unknowns], dtype=int),
                    unknowns=np.concatenate(self.unknowns) if self.unknowns else np.zeros(0),
                )

        write_atomic(path, write)

    @classmethod
    def load(cls, path: str | Path) -> "State":
        """A state written by :meth:`save`.

        ``ValueError`` naming the file and what is wrong if it is not one: missing or
        unreadable, not an ``.npz`` archive, an array missing or of the wrong shape or type
        (:data:`SAVED`), a value not finite, or slider sizes that do not add up.  Every array's
        header is read, and its size checked against the archive's, before it is read."""
        try:
            arrays = _saved_arrays(Path(path))
        except FileNotFoundError:
            raise ValueError(f"{path}: no such file") from None
        except IsADirectoryError:
            raise ValueError(f"{path}: a directory, not a saved integrator state") from None
        except OSError as exc:
            raise ValueError(f"{path}: cannot read the file ({exc.strerror or exc})") from None
        except DAMAGED as exc:
            raise ValueError(f"{path}: not a saved integrator state ({exc})") from None
        sizes, unknowns = arrays["sizes"], arrays["unknowns"]
        if sizes.dtype.kind not in "iu" or np.any(sizes < 0) or sizes.sum() != len(unknowns):
            raise ValueError(
                f"{path}: not a saved integrator state (its slider sizes {sizes.tolist()} "
                f"do not add up to its {len(unknowns)} unknowns)"
            )
        lengths = {key: len(arrays[key]) for key in ("q", "v", "a", "qdd")}
        if len(set(lengths.values())) > 1:
            raise ValueError(
                f"{path}: not a saved integrator state (q, v, a, qdd of lengths "
                f"{list(lengths.values())})"
            )
        for key, value in arrays.items():
            if key != "sizes" and not np.all(np.isfinite(value)):
                raise ValueError(f"{path}: not a saved integrator state ({key} is not finite)")
        split = np.split(unknowns, np.cumsum(sizes)[:-1]) if sizes.size else []
        return cls(
            float(arrays["t"]),
            arrays["q"].astype(float),
            arrays["v"].astype(float),
            arrays["a"].astype(float),
            arrays["qdd"].astype(float),
            [np.array(y, dtype=float) for y in split],
            float(arrays["h"]),
        )


#: What :mod:`zipfile` and numpy's ``.npy`` reader raise for a damaged archive (besides
#: ``ValueError``: ``RuntimeError`` for a member flagged encrypted, ``NotImplementedError`` for
#: an unknown compression, ``EOFError`` and ``zlib.error`` for cut or garbled data).
DAMAGED = (zipfile.BadZipFile, zlib.error, EOFError, ValueError, NotImplementedError, RuntimeError)
#: The arrays :meth:`State.save` writes: name and number of dimensions.
SAVED = {"t": 0, "q": 1, "v": 1, "a": 1, "qdd": 1, "h": 0, "sizes": 1, "unknowns": 1}


def _saved_arrays(path: Path) -> dict[str, np.ndarray]:
    """The arrays of :data:`SAVED` in the ``.npz`` archive ``path``, real numbers each, of its
    number of dimensions (``ValueError`` otherwise); every header is checked before the data
    is read, so that a header claiming more data than the archive holds allocates nothing."""
    arrays = {}
    with zipfile.ZipFile(path) as archive:
        for name, ndim in SAVED.items():
            try:
                info = archive.getinfo(f"{name}.npy")
            except KeyError:
                raise ValueError(f"no array {name!r}") from None
            with archive.open(info) as member:
                version = npy.read_magic(member)
                header = (
                    npy.read_array_header_1_0 if version == (1, 0) else npy.read_array_header_2_0
                )
                shape, _, dtype = header(member)
            if len(shape) != ndim or dtype.kind not in "fiu":
                raise ValueError(
                    f"{name!r} is an array of {dtype} and shape {shape}; "
                    f"a saved state's is real and {ndim}-dimensional"
                )
            if int(np.prod(shape)) * dtype.itemsize > info.file_size:
                raise ValueError(f"{name!r} claims more data than the archive holds")
            with archive.open(info) as member:
                arrays[name] = npy.read_array(member, allow_pickle=False)
    return arrays
