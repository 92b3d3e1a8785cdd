"""Beam cross-section properties: 6x6 stiffness, mass per unit length, section inertia."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from fvbeam.geometry import inertia3, number

if TYPE_CHECKING:
    from fvbeam.shapes import Material, Shape

#: Order of the generalised strains and stresses in the section frame (t, e2, e3):
#: axial, two shears, twist, two bending curvatures.
COMPONENTS = ("EA", "GAy", "GAz", "GJ", "EJy", "EJz")
#: Smallest ratio of a section stiffness' smallest eigenvalue to its largest (its condition
#: number at most ``1e14``).  ``numpy.linalg.eigvalsh`` is backward stable: the eigenvalues of
#: a 6x6 matrix come out to about ``6 eps = 1.3e-15`` of the largest, so one below ``1e-14`` of
#: it is within ten round-off units of zero, its sign unknown, and a solve with such a
#: stiffness keeps none of the smallest one's digits.
CONDITIONING = 1e-14


@dataclass(frozen=True, eq=False)
class Section:
    """Linear elastic section in its own frame ``(t, e2, e3)``.

    Parameters
    ----------
    stiffness
        6x6 matrix relating ``[F_t, F_2, F_3, M_t, M_2, M_3]`` to the generalised strains
        ``[nu_t, nu_2, nu_3, kappa_t, kappa_2, kappa_3]``; symmetric positive definite.
    mass_per_length
        Mass per unit length (for dynamics), >= 0.
    inertia
        Section inertia per unit length in the section frame (for dynamics): a symmetric
        positive semi-definite 3x3 matrix, or its three principal values (a diagonal
        matrix), as a scene's ``inertia``.
    name
        Label used in error messages.
    shape
        The cross-section's shape (:mod:`fvbeam.shapes`) when the section was built from it
        (:meth:`from_shape`), for drawing; None when it is given by its numbers.
    """

    stiffness: np.ndarray
    mass_per_length: float = 0.0
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    name: str = "section"
    shape: Shape | None = None

    def __post_init__(self) -> None:
        K = np.array(self.stiffness, dtype=float)
        if K.shape != (6, 6):
            raise ValueError(f"{self.name}: stiffness must be 6x6, got shape {K.shape}")
        if not np.all(np.isfinite(K)):
            raise ValueError(f"{self.name}: stiffness has a non-finite entry")
        if not np.allclose(K, K.T, rtol=1e-12, atol=1e-12 * np.abs(K).max()):
            raise ValueError(f"{self.name}: stiffness must be symmetric")
        _check_definite(K, self.name)
        m = number(self.mass_per_length, f"{self.name}: mass_per_length", ">= 0")
        J = inertia3(self.inertia, f"{self.name}: inertia")
        object.__setattr__(self, "stiffness", K)
        object.__setattr__(self, "mass_per_length", m)
        object.__setattr__(self, "inertia", J)

    @classmethod
    def diagonal(
        cls,
        EA: float,
        GAy: float,
        GAz: float,
        GJ: float,
        EJy: float,
        EJz: float,
        mass_per_length: float = 0.0,
        inertia: ArrayLike = (0.0, 0.0, 0.0),
        name: str = "section",
    ) -> "Section":
        """Uncoupled section from its six stiffnesses (named as in :data:`COMPONENTS`), with
        the inputs of a scene's ``[[section]]``: ``inertia`` three principal values (or a
        3x3 matrix), ``mass_per_length`` and ``name``.  A value that is not a finite number
        in range raises ``ValueError`` naming it.  The stiffnesses are the diagonal of the
        6x6 stiffness, in the order of the generalised strains (eq. T2):

        >>> section = Section.diagonal(EA=1e9, GAy=1e8, GAz=1e8, GJ=3e4, EJy=4e4, EJz=4e4)
        >>> section.stiffness.diagonal().tolist()
        [1000000000.0, 100000000.0, 100000000.0, 30000.0, 40000.0, 40000.0]
        """
        values = dict(EA=EA, GAy=GAy, GAz=GAz, GJ=GJ, EJy=EJy, EJz=EJz)
        for key, value in values.items():
            values[key] = number(value, f"{name}: {key}", "> 0")
        stiffness = np.diag([values[k] for k in COMPONENTS])
        return cls(stiffness, mass_per_length, inertia3(inertia, f"{name}: inertia"), name)

    @classmethod
    def from_shape(cls, material: Material, shape: Shape, name: str = "section") -> Section:
        """Uncoupled section of ``material`` and ``shape`` (:mod:`fvbeam.shapes`: the
        formulas and their sources): ``EA = E A``, ``GAy = G A_2``, ``GAz = G A_3`` (shear
        areas with Cowper's coefficients), ``GJ = G K`` (torsion constant), ``EJy = E I_2``,
        ``EJz = E I_3``; mass per length ``rho A`` and inertia ``rho diag(I_2 + I_3, I_2,
        I_3)``.  The material and the shape check their own values.

        A steel tube, 60 mm by 50 mm: ``EJ = E pi (D^4 - d^4) / 64``.

        >>> from fvbeam.shapes import Material, Tube
        >>> steel = Material(E=210e9, nu=0.3, density=7850.0)
        >>> section = Section.from_shape(steel, Tube(outer=0.06, inner=0.05))
        >>> round(section.stiffness[4, 4]), round(section.mass_per_length, 3)
        (69169, 6.782)
        """
        E, G, rho = material.E, material.shear_modulus, material.density
        A, K = shape.area(), shape.torsion_constant()
        I2, I3 = shape.second_moments()
        A2, A3 = shape.shear_areas(material.poisson)
        numbers = cls.diagonal(
            E * A,
            G * A2,
            G * A3,
            G * K,
            E * I2,
            E * I3,
            mass_per_length=rho * A,
            inertia=(rho * (I2 + I3), rho * I2, rho * I3),
            name=name,
        )
        return replace(numbers, shape=shape)

    def global_stiffness(self, frames: np.ndarray) -> np.ndarray:
        """Stiffness in global axes, ``blockdiag(R, R) C blockdiag(R, R)^T`` (eq. T2).

        ``frames``: section frames ``R = [t, e2, e3]``, shape (..., 3, 3).
        """
        R6 = np.zeros(frames.shape[:-2] + (6, 6))
        R6[..., :3, :3] = frames
        R6[..., 3:, 3:] = frames
        return R6 @ self.stiffness @ np.swapaxes(R6, -1, -2)


def _check_definite(K: np.ndarray, name: str) -> None:
    """``ValueError`` unless the symmetric ``K`` is positive definite with its smallest
    eigenvalue above :data:`CONDITIONING` times its largest; the message names the stiffnesses
    (a diagonal ``K``) or the eigenvalues at fault and the rule."""
    eig = np.linalg.eigvalsh(K)
    diag = np.diag(K)
    bad = [f"{n} = {v:g}" for n, v in zip(COMPONENTS, diag, strict=True) if not v > 0]
    if bad or not eig.min() > 0:
        detail = ", ".join(bad) if bad else f"smallest eigenvalue {eig.min():g}"
        raise ValueError(f"{name}: stiffness must be positive definite ({detail})")
    if eig.min() <= CONDITIONING * eig.max():
        if np.count_nonzero(K - np.diag(diag)) == 0:
            low, high = np.argmin(diag), np.argmax(diag)
            small, large = (
                f"{COMPONENTS[low]} = {diag[low]:g}",
                f"{COMPONENTS[high]} = {diag[high]:g}",
            )
        else:
            small, large = f"eigenvalue {eig.min():g}", f"eigenvalue {eig.max():g}"
        raise ValueError(
            f"{name}: stiffness is too ill-conditioned: its smallest {small} is "
            f"{eig.min() / eig.max():.3g} of its largest {large}; a section's smallest "
            f"eigenvalue must exceed {CONDITIONING:g} of its largest (double precision "
            "resolves no digit of a smaller one)"
        )
