"""Section properties from a material and a cross-section shape (``docs/scenes.md``,
"Sections from material and shape").

A :class:`Material` (Young's modulus ``E``, Poisson's ratio ``nu`` or shear modulus ``G``,
``density``) and a shape (:class:`Circle`, :class:`Tube`, :class:`Rectangle`,
:class:`ISection`) give the six stiffnesses of an uncoupled section in its frame
``(t, e2, e3)`` (:meth:`fvbeam.section.Section.from_shape`):

``EA = E A``, ``GAy = G A_2``, ``GAz = G A_3``, ``GJ = G K``, ``EJy = E I_2``, ``EJz = E I_3``

with ``A`` the area, ``I_2 = int x3^2 dA`` and ``I_3 = int x2^2 dA`` the second moments about
``e2`` and ``e3`` (``x2``, ``x3`` the coordinates along ``e2``, ``e3`` from the centroid),
``K`` the torsion constant (Saint-Venant), ``A_2``, ``A_3`` the shear areas along ``e2``,
``e3`` (``k A`` with ``k`` the shear coefficient of Timoshenko's beam); the mass per length
``rho A`` and the section inertia per length ``rho diag(I_2 + I_3, I_2, I_3)`` (the polar
moment ``I_2 + I_3`` about ``t``, not ``K``).  Every shape is doubly symmetric: centroid and
shear centre coincide, the axes ``e2``, ``e3`` are principal, nothing couples.

Shear coefficients: Cowper, "The shear coefficient in Timoshenko's beam theory", J. Appl.
Mech. 33 (1966) 335-340, Table 1, from the flexure solution of three-dimensional elasticity
(they depend on ``nu``):

- solid circle ``k = 6 (1 + nu) / (7 + 6 nu)``;
- tube, ``m = inner / outer``: ``k = 6 (1 + nu) (1 + m^2)^2 / ((7 + 6 nu) (1 + m^2)^2 +
  (20 + 12 nu) m^2)`` (the circle at ``m = 0``, the thin tube's ``2 (1 + nu) / (4 + 3 nu)``
  as ``m -> 1``);
- rectangle ``k = 10 (1 + nu) / (12 + 11 nu)`` in both directions.  Cowper's value ignores
  the anticlastic curvature of a section wider than deep: it holds for a depth (along the
  shear) at least the width; for a wide, shallow section the true coefficient is lower, the
  more so the wider (Hutchinson, J. Appl. Mech. 68 (2001) 87-92): the shear stiffness there
  is too high;
- thin-walled I-section, shear along the web (``e3``): ``k = 10 (1 + nu) (1 + 3 m)^2 / ((12
  + 72 m + 150 m^2 + 90 m^3) + nu (11 + 66 m + 135 m^2 + 90 m^3) + 30 n^2 (m + m^2) + 5 nu n^2
  (8 m + 9 m^2))``, ``m = 2 b t_f / (h_c t_w)``, ``n = b / h_c``, ``h_c = h - t_f`` the
  distance between the flanges' mid-planes (the rectangle's at ``m = 0``).  Along the
  flanges (``e2``) the two flanges carry the shear as rectangles of their own,
  ``A_2 = k_rect 2 b t_f`` (the web, thin in that direction, neglected).

Torsion constants: the circle and the tube ``K = pi (D^4 - d^4) / 32`` (exact); the
rectangle of sides ``a >= c`` by its series (Timoshenko and Goodier, *Theory of Elasticity*,
3rd ed., 1970, Sec. 109): ``K = a c^3 [1/3 - (64 / pi^5) (c / a) sum_{n odd} tanh(n pi a /
(2 c)) / n^5]``, summed as ``(31/32) zeta(5)`` less the exponentially small ``sum (1 - tanh) /
n^5`` (exact to round-off); the I-section as a thin-walled open section, the sum of its
walls' ``length thickness^3 / 3`` along their mid-lines, ``K = (2 b t_f^3 + (h - t_f) t_w^3)
/ 3`` (Roark's Formulas for Stress and Strain, 7th ed., Table 10.7; the fillets and the
junctions' extra stiffness neglected: valid for thin walls, ``t_f``, ``t_w`` much less than
``b``, ``h``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from fvbeam.geometry import number

#: Odd terms of the rectangle's torsion series kept beyond ``(31/32) zeta(5)``: the complement
#: ``1 - tanh(n pi a / (2 c)) = 2 expit(-n pi a / c) <= 2 exp(-n pi)`` is below ``1e-31`` at
#: ``n = 23``, far under round-off of the leading ``1 / 3``.
TORSION_TERMS = 12


@dataclass(frozen=True)
class Material:
    """A linear elastic isotropic material: Young's modulus ``E`` (Pa), exactly one of
    Poisson's ratio ``nu`` (in ``(-1, 1/2)``) and shear modulus ``G`` (Pa; ``nu = E / (2 G) -
    1`` then in that range), ``density`` (kg/m^3, 0 for a massless section); ``name`` labels
    errors.  A value out of range raises ``ValueError`` naming its key.

    >>> steel = Material(E=210e9, nu=0.3, density=7850.0)
    >>> round(steel.shear_modulus / 1e9, 4)
    80.7692
    """

    E: float
    nu: float | None = None
    G: float | None = None
    density: float = 0.0
    name: str = "material"

    def __post_init__(self) -> None:
        number(self.E, f"{self.name}: E", "> 0")
        number(self.density, f"{self.name}: density", ">= 0")
        if (self.nu is None) == (self.G is None):
            raise ValueError(f"{self.name}: give exactly one of nu, G (the other follows)")
        if self.G is not None:
            number(self.G, f"{self.name}: G", "> 0")
        nu = self.poisson
        if not -1 < nu < 0.5:
            key = "nu" if self.nu is not None else "G (nu = E / (2 G) - 1)"
            raise ValueError(
                f"{self.name}: {key} must give a Poisson's ratio in (-1, 0.5) "
                f"(a stable isotropic material), got nu = {nu:g}"
            )

    @property
    def poisson(self) -> float:
        """Poisson's ratio ``nu``, given or ``E / (2 G) - 1``."""
        if self.nu is not None:
            return number(self.nu, f"{self.name}: nu")
        assert self.G is not None
        return self.E / (2 * self.G) - 1

    @property
    def shear_modulus(self) -> float:
        """Shear modulus ``G``, given or ``E / (2 (1 + nu))``."""
        return self.G if self.G is not None else self.E / (2 * (1 + self.poisson))


class Shape(Protocol):
    """What a section reads of a shape (module doc): every length in metres."""

    def area(self) -> float: ...

    def second_moments(self) -> tuple[float, float]:
        """``(I_2, I_3)``: about ``e2`` and ``e3``."""
        ...

    def torsion_constant(self) -> float: ...

    def shear_areas(self, nu: float) -> tuple[float, float]:
        """``(A_2, A_3)``: along ``e2`` and ``e3``, for Poisson's ratio ``nu``."""
        ...

    def enclosing_radius(self) -> float:
        """The radius of the smallest circle about the centroid holding the section (its
        size in a picture)."""
        ...


def _positive(shape: object, *keys: str) -> None:
    for key in keys:
        number(getattr(shape, key), f"shape.{key}", "> 0")


def _below(key: str, value: float, limit: float, of: str) -> None:
    if not value < limit:
        raise ValueError(f"shape.{key} must be less than {of} = {limit:g}, got {value:g}")


def rectangle_coefficient(nu: float) -> float:
    """Cowper's shear coefficient of a rectangle, ``10 (1 + nu) / (12 + 11 nu)``."""
    return 10 * (1 + nu) / (12 + 11 * nu)


@dataclass(frozen=True)
class Tube:
    """A circular tube of ``outer`` and ``inner`` diameters (``0 <= inner < outer``).

    >>> round(Tube(outer=2.0, inner=0.0).shear_areas(0.3)[0] / np.pi, 4)  # 6 1.3 / 8.8
    0.8864
    """

    outer: float
    inner: float = 0.0

    def __post_init__(self) -> None:
        _positive(self, "outer")
        number(self.inner, "shape.inner", ">= 0")
        _below("inner", self.inner, self.outer, "shape.outer")

    def area(self) -> float:
        return np.pi * (self.outer**2 - self.inner**2) / 4

    def second_moments(self) -> tuple[float, float]:
        I = np.pi * (self.outer**4 - self.inner**4) / 64
        return I, I

    def torsion_constant(self) -> float:
        return np.pi * (self.outer**4 - self.inner**4) / 32

    def shear_areas(self, nu: float) -> tuple[float, float]:
        m2 = (self.inner / self.outer) ** 2
        k = 6 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)
        return k * self.area(), k * self.area()

    def enclosing_radius(self) -> float:
        """The outer radius, ``outer / 2``."""
        return self.outer / 2


@dataclass(frozen=True)
class Circle:
    """A solid circle of ``diameter``: a :class:`Tube` without a bore."""

    diameter: float

    def __post_init__(self) -> None:
        _positive(self, "diameter")

    @property
    def tube(self) -> Tube:
        return Tube(outer=self.diameter)

    def area(self) -> float:
        return self.tube.area()

    def second_moments(self) -> tuple[float, float]:
        return self.tube.second_moments()

    def torsion_constant(self) -> float:
        return self.tube.torsion_constant()

    def shear_areas(self, nu: float) -> tuple[float, float]:
        return self.tube.shear_areas(nu)

    def enclosing_radius(self) -> float:
        return self.tube.enclosing_radius()


@dataclass(frozen=True)
class Rectangle:
    """A solid rectangle, ``width`` along ``e2`` by ``height`` along ``e3``."""

    width: float
    height: float

    def __post_init__(self) -> None:
        _positive(self, "width", "height")

    def area(self) -> float:
        return self.width * self.height

    def second_moments(self) -> tuple[float, float]:
        b, h = self.width, self.height
        return b * h**3 / 12, h * b**3 / 12

    def torsion_constant(self) -> float:
        """The series of Timoshenko and Goodier (module doc), sides ``a >= c``."""
        from scipy.special import expit, zeta  # a tenth of a second: a rectangle's only

        a, c = max(self.width, self.height), min(self.width, self.height)
        n = np.arange(1, 2 * TORSION_TERMS, 2)
        rest = np.sum(2 * expit(-n * np.pi * a / c) / n**5)
        series = 31 / 32 * zeta(5) - rest
        return float(a * c**3 * (1 / 3 - 64 / np.pi**5 * (c / a) * series))

    def shear_areas(self, nu: float) -> tuple[float, float]:
        k = rectangle_coefficient(nu)
        return k * self.area(), k * self.area()

    def enclosing_radius(self) -> float:
        """Half the diagonal, ``sqrt(width^2 + height^2) / 2`` (the corners on the circle)."""
        return float(np.hypot(self.width, self.height)) / 2


@dataclass(frozen=True)
class ISection:
    """A doubly symmetric I-section: overall ``height`` along ``e3`` (the web's direction),
    flange ``width`` along ``e2``, ``web`` and ``flange`` thicknesses; sharp corners, no
    fillets."""

    height: float
    width: float
    web: float
    flange: float

    def __post_init__(self) -> None:
        _positive(self, "height", "width", "web", "flange")
        _below("flange", self.flange, self.height / 2, "half shape.height")
        if self.web > self.width:
            raise ValueError(
                f"shape.web must be at most shape.width = {self.width:g}, got {self.web:g}"
            )

    def area(self) -> float:
        return 2 * self.width * self.flange + (self.height - 2 * self.flange) * self.web

    def second_moments(self) -> tuple[float, float]:
        b, h, tw, tf = self.width, self.height, self.web, self.flange
        hw = h - 2 * tf
        return (b * h**3 - (b - tw) * hw**3) / 12, (2 * tf * b**3 + hw * tw**3) / 12

    def torsion_constant(self) -> float:
        b, h, tw, tf = self.width, self.height, self.web, self.flange
        return (2 * b * tf**3 + (h - tf) * tw**3) / 3

    def shear_areas(self, nu: float) -> tuple[float, float]:
        b, tw, tf = self.width, self.web, self.flange
        hc = self.height - tf
        m, n2 = 2 * b * tf / (hc * tw), (b / hc) ** 2
        k3 = (
            10
            * (1 + nu)
            * (1 + 3 * m) ** 2
            / (
                (12 + 72 * m + 150 * m**2 + 90 * m**3)
                + nu * (11 + 66 * m + 135 * m**2 + 90 * m**3)
                + 30 * n2 * (m + m**2)
                + 5 * nu * n2 * (8 * m + 9 * m**2)
            )
        )
        return rectangle_coefficient(nu) * 2 * b * tf, k3 * self.area()

    def enclosing_radius(self) -> float:
        """Half the diagonal of the bounding rectangle, ``sqrt(width^2 + height^2) / 2`` (the
        flanges' tips on the circle)."""
        return float(np.hypot(self.width, self.height)) / 2


#: The shapes by the ``kind`` a scene names them with.
SHAPES: dict[str, type] = {"circle": Circle, "tube": Tube, "rectangle": Rectangle, "I": ISection}
