"""Sections from a material and a shape (fvbeam.shapes, Section.from_shape) against handbook
formulas written here independently (radii instead of diameters, the parallel-axis theorem
instead of differences of rectangles), the rectangle's torsion against Timoshenko and
Goodier's table, Cowper's shear coefficients against their published values and limits."""

import math

import numpy as np
import pytest

from fvbeam import Section
from fvbeam.section import COMPONENTS
from fvbeam.shapes import Circle, ISection, Material, Rectangle, Tube

EPS = np.finfo(float).eps
#: Products and sums of a few terms: a handful of roundings, each at most eps / 2.
ROUND = 8 * EPS
STEEL = Material(E=210e9, nu=0.3, density=7850.0)
E, NU, RHO = 210e9, 0.3, 7850.0
G = E / (2 * (1 + NU))


def stiffness(section: Section) -> dict[str, float]:
    return dict(zip(COMPONENTS, section.stiffness.diagonal(), strict=True))


def assert_section(section: Section, A, I2, I3, K, A2, A3, rtol=ROUND):
    """The section of ``E``, ``G``, ``RHO`` with these area properties (module doc of
    fvbeam.shapes: EA = E A ... and rho diag(I2 + I3, I2, I3))."""
    expected = dict(EA=E * A, GAy=G * A2, GAz=G * A3, GJ=G * K, EJy=E * I2, EJz=E * I3)
    got = stiffness(section)
    for key in COMPONENTS:
        assert got[key] == pytest.approx(expected[key], rel=rtol, abs=0), key
    assert section.mass_per_length == pytest.approx(RHO * A, rel=rtol, abs=0)
    np.testing.assert_allclose(
        section.inertia, np.diag([RHO * (I2 + I3), RHO * I2, RHO * I3]), rtol=rtol, atol=0
    )


def cowper_circle(nu):
    return 6 * (1 + nu) / (7 + 6 * nu)


def cowper_rectangle(nu):
    return 10 * (1 + nu) / (12 + 11 * nu)


def test_cowper_coefficients_are_his_tabulated_values():
    """Cowper (1966), Table 1, at nu = 0.3: solid circle 0.886, rectangle 0.850, thin-walled
    round tube 0.531, printed to three digits (half a unit of the last one)."""
    assert abs(cowper_circle(0.3) - 0.886) <= 5e-4
    assert abs(cowper_rectangle(0.3) - 0.850) <= 5e-4
    thin = Tube(outer=1.0, inner=1.0 - 1e-6).shear_areas(0.3)[0] / Tube(1.0, 1.0 - 1e-6).area()
    assert abs(thin - 2 * 1.3 / 4.9) <= 5e-4  # 2 (1 + nu) / (4 + 3 nu)


def test_solid_circle():
    """Roark, Table A.1, circle of radius R: A = pi R^2, I = pi R^4 / 4, K = pi R^4 / 2
    (exact for the circle); Cowper's k on both axes."""
    R = 0.0125
    A, I = math.pi * R**2, math.pi * R**4 / 4
    k = cowper_circle(NU)
    section = Section.from_shape(STEEL, Circle(diameter=2 * R))
    assert_section(section, A, I, I, 2 * I, k * A, k * A)


def test_tube():
    """Roark, Table A.1, hollow circle of radii R > r: A = pi (R^2 - r^2), I = pi (R^4 -
    r^4) / 4, K = 2 I (exact); Cowper's hollow-circle k with m = r / R."""
    R, r = 0.03, 0.025
    A, I = math.pi * (R**2 - r**2), math.pi * (R**4 - r**4) / 4
    m = r / R
    k = 6 * (1 + NU) * (1 + m**2) ** 2 / ((7 + 6 * NU) * (1 + m**2) ** 2 + (20 + 12 * NU) * m**2)
    section = Section.from_shape(STEEL, Tube(outer=2 * R, inner=2 * r))
    assert_section(section, A, I, I, 2 * I, k * A, k * A)


def test_a_tube_without_a_bore_is_the_circle():
    a = Section.from_shape(STEEL, Tube(outer=0.05, inner=0.0))
    b = Section.from_shape(STEEL, Circle(diameter=0.05))
    np.testing.assert_array_equal(a.stiffness, b.stiffness)


def test_rectangle():
    """Roark, Table A.1, rectangle b (along e2) by h (along e3): A = b h, I_2 = b h^3 / 12,
    I_3 = h b^3 / 12; the torsion constant from the table below (to its rounding), so here
    taken from the shape; Cowper's rectangle k."""
    b, h = 0.02, 0.05
    shape = Rectangle(width=b, height=h)
    k = cowper_rectangle(NU)
    section = Section.from_shape(STEEL, shape)
    K = shape.torsion_constant()
    assert_section(section, b * h, b * h**3 / 12, h * b**3 / 12, K, k * b * h, k * b * h)
    swapped = Section.from_shape(STEEL, Rectangle(width=h, height=b))
    assert stiffness(swapped)["EJy"] == stiffness(section)["EJz"]
    assert stiffness(swapped)["GJ"] == stiffness(section)["GJ"]


#: Timoshenko and Goodier, Theory of Elasticity (1970), Sec. 109, table of the torsion of a
#: rectangle of sides a >= c: K = k1 a c^3, k1 printed to three decimals.
TORSION_TABLE = {
    1.0: 0.141,
    1.5: 0.196,
    2.0: 0.229,
    2.5: 0.249,
    3.0: 0.263,
    4.0: 0.281,
    5.0: 0.291,
    10.0: 0.312,
}


@pytest.mark.parametrize("ratio", TORSION_TABLE)
def test_rectangle_torsion_constant_is_the_table(ratio):
    """k1 = K / (a c^3) to half a unit of the table's last digit; either orientation."""
    c = 0.01
    for shape in (Rectangle(width=ratio * c, height=c), Rectangle(width=c, height=ratio * c)):
        k1 = shape.torsion_constant() / (ratio * c * c**3)
        assert abs(k1 - TORSION_TABLE[ratio]) <= 5e-4 + ROUND


def test_thin_rectangle_torsion_tends_to_roarks_strip():
    """A strip (a / c = 1e4): K = (a c^3 / 3) (1 - 0.630 c / a) (Roark, Table 10.7, the thin
    rectangle), 0.630 printed to three digits: within half a unit of it, 0.0005 c / (3 a),
    of k1 (the series' next term, e^(-pi a / c), nil)."""
    a, c = 1.0, 1e-4
    k1 = Rectangle(width=a, height=c).torsion_constant() / (a * c**3)
    assert abs(k1 - (1 - 0.630 * c / a) / 3) <= 0.0005 * c / (3 * a) + ROUND


def test_i_section():
    """A thin-walled I (flange b x t_f, web t_w, overall depth h): area and I_2 by the
    parallel-axis theorem on three rectangles (Roark, Table A.1), I_3 the flanges' and the
    web's own; K the sum of the walls' l t^3 / 3 along their mid-lines (Roark, Table 10.7);
    k_3 Cowper's I-section coefficient (shear along the web), A_2 the flanges as rectangles."""
    h, b, tw, tf = 0.2, 0.1, 0.0056, 0.0085  # an IPE 200 without its fillets
    hw = h - 2 * tf
    A = 2 * b * tf + hw * tw
    arm = (h - tf) / 2
    I2 = 2 * (b * tf**3 / 12 + b * tf * arm**2) + tw * hw**3 / 12
    I3 = 2 * tf * b**3 / 12 + hw * tw**3 / 12
    K = (2 * b * tf**3 + (h - tf) * tw**3) / 3
    hc = h - tf
    m, n = 2 * b * tf / (hc * tw), b / hc
    k3 = (10 * (1 + NU) * (1 + 3 * m) ** 2) / (
        12
        + 72 * m
        + 150 * m**2
        + 90 * m**3
        + NU * (11 + 66 * m + 135 * m**2 + 90 * m**3)
        + 30 * n**2 * (m + m**2)
        + 5 * NU * n**2 * (8 * m + 9 * m**2)
    )
    A2 = cowper_rectangle(NU) * 2 * b * tf
    section = Section.from_shape(STEEL, ISection(height=h, width=b, web=tw, flange=tf))
    # I2 here sums terms of both signs' worth of cancellation (b h^3 - (b - tw) hw^3 in the
    # shape): 1e-14 covers the cancellation factor b h^3 / I2 = 2.2 times a few eps
    assert_section(section, A, I2, I3, K, A2, k3 * A, rtol=1e-14)


def test_i_section_with_vanishing_flanges_tends_to_the_web_rectangle():
    """Cowper's I coefficient at m = 0 is his rectangle's: with flanges 1e-6 of the web's
    area, k_3 differs from it by O(m) (coefficients of order 100: within 1e-3)."""
    shape = ISection(height=0.2, width=0.01, web=0.01, flange=1e-7)
    k3 = shape.shear_areas(NU)[1] / shape.area()
    assert abs(k3 - cowper_rectangle(NU)) <= 1e-3


def test_shear_modulus_or_poisson_ratio():
    """G given: nu = E / (2 G) - 1 and the same section as with that nu."""
    by_G = Material(E=E, G=G, density=RHO)
    assert by_G.poisson == pytest.approx(NU, rel=ROUND)
    a = Section.from_shape(by_G, Tube(0.06, 0.05))
    b = Section.from_shape(STEEL, Tube(0.06, 0.05))
    np.testing.assert_allclose(a.stiffness, b.stiffness, rtol=ROUND, atol=0)


def test_no_density_is_a_massless_section():
    section = Section.from_shape(Material(E=E, nu=NU), Circle(0.02))
    assert section.mass_per_length == 0 and not section.inertia.any()


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Material(E=E), r"give exactly one of nu, G"),
        (lambda: Material(E=E, nu=0.3, G=G), r"give exactly one of nu, G"),
        (lambda: Material(E=E, nu=0.5), r"nu must give a Poisson's ratio in \(-1, 0.5\)"),
        (lambda: Material(E=E, G=E / 4), r"G \(nu = E / \(2 G\) - 1\) must give .* nu = 1$"),
        (lambda: Material(E=-1.0, nu=0.3), r"E must be finite and > 0, got -1.0"),
        (lambda: Material(E=E, nu=0.3, density=-1.0), r"density must be finite and >= 0"),
        (lambda: Tube(outer=0.05, inner=0.05), r"shape.inner must be less than shape.outer"),
        (lambda: Tube(outer=0.05, inner=-0.01), r"shape.inner must be finite and >= 0"),
        (lambda: Circle(diameter=0.0), r"shape.diameter must be finite and > 0"),
        (lambda: Rectangle(width=0.1, height=np.nan), r"shape.height must be finite and > 0"),
        (lambda: ISection(0.2, 0.1, 0.11, 0.01), r"shape.web must be at most shape.width"),
        (
            lambda: ISection(0.2, 0.1, 0.01, 0.1),
            r"shape.flange must be less than half shape.height = 0.1, got 0.1",
        ),
    ],
)
def test_bad_material_or_shape_is_named(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_a_section_keeps_its_shape_for_drawing():
    shape = Tube(outer=0.06, inner=0.05)
    assert Section.from_shape(STEEL, shape).shape == shape
    assert Section.diagonal(1.0, 1.0, 1.0, 1.0, 1.0, 1.0).shape is None
