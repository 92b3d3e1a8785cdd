"""The compiled smeared load transfer (``sliders/lines/batched_kernel.py``,
``smeared_transfer``) against the kernel form it compiles (``BeamChain.transfer``, eq. T6).

The chains are those of ``tests/test_stack.py``: one to three beams (fv2, fv3, galerkin-p1,
galerkin-p2; straight and circular-arc), every member moved by its own random shift, queried
at the chain's ends, beam junctions, vertices, mid nodes, evaluation points (on them, within
half the tie distance and 1e-9 of the element off them) and random abscissae; the kernel's
half-width runs from a tenth of the shortest element to one and a half of the longest.

Tolerances: the compiled transfer and the form integrate the same piecewise polynomial by the
same rule on the same pieces, so they differ by roundoff, bounded in
``tests/test_stack.py`` (``Bounds.smeared``).  The derivative against a central difference
of ``G`` over ``+-d``: away from the abscissae where ``G`` is not smooth, the difference is
``G'`` within ``d^2 / 6 max|G'''|`` plus the roundoff of the two values over ``2 d``
(:func:`third_derivative_bound`).
"""

import numpy as np
import pytest
from test_stack import CHAINS, Bounds, kernel_mass, scattered, stack_of

from fvbeam import Structure
from fvbeam.elements import evaluation_points
from fvbeam.pointwise import kernel_at
from fvbeam.smearing import density, slope
from sliders.lines.batched import ChainStack
from sliders.lines.chain import BeamChain

KERNELS = ("box", "hat")


def element_lengths(chain: BeamChain) -> np.ndarray:
    return np.concatenate([beam.mesh.element_length for beam in chain.beams])


def half_widths(chain: BeamChain, rng: np.random.Generator) -> list[float]:
    """A tenth of the shortest element, a random fraction (0.1 to 1.5) of the mean one, one
    and a half of the longest."""
    h = element_lengths(chain)
    return [0.1 * h.min(), float(rng.uniform(0.1, 1.5) * h.mean()), 1.5 * h.max()]


def test_kernel_at_is_the_smearing_kernel():
    """The compiled kernel evaluates :func:`fvbeam.smearing.density` and
    :func:`~fvbeam.smearing.slope` by the same operations: equal exactly, inside, on the
    edges (outside: the support is open), at the peak and outside."""
    rng = np.random.default_rng(1)
    for smearing in (0.03, 1.0, 2.7):
        r = np.concatenate(
            [rng.uniform(-1.5, 1.5, 50) * smearing, smearing * np.array([-1.0, 0.0, 1.0])]
        )
        for kernel in KERNELS:
            compiled = np.array([kernel_at(x, smearing, kernel == "box") for x in r])
            np.testing.assert_array_equal(compiled[:, 0], density(r, smearing, kernel))
            np.testing.assert_array_equal(compiled[:, 1], slope(r, smearing, kernel))


def check_against_the_form(stack, chains, xi, q, smearing, kernel):
    """Every member's compiled smeared transfer against its chain's kernel form: on the form's
    dofs within :meth:`Bounds.smeared`, exactly zero on the other dofs it lists."""
    dofs, G, dG = stack.transfer(xi, smearing, kernel)
    for b, (chain, x) in enumerate(zip(chains, xi, strict=True)):
        form_dofs, form_G, form_dG = chain.transfer(float(x), smearing, kernel)
        tol_G, tol_dG = Bounds(chain, x, q[b]).smeared(smearing, kernel)
        assert np.isin(form_dofs, dofs[b]).all()
        extra = ~np.isin(dofs[b], form_dofs)
        assert not np.any(G[b, extra]) and not np.any(dG[b, extra])
        n = chain.structure.n_dofs
        for compiled, form, tol in ((G, form_G, tol_G), (dG, form_dG, tol_dG)):
            np.testing.assert_allclose(
                scattered(dofs[b], compiled[b], n),
                scattered(form_dofs, form, n),
                rtol=0,
                atol=tol,
            )
    return dofs, G, dG


@pytest.mark.parametrize("name", CHAINS)
@pytest.mark.parametrize("kernel", KERNELS)
def test_compiled_smeared_transfer_equals_the_form(name, kernel):
    """``G`` and ``dG/dxi`` of every member equal the form's to roundoff, for three half-widths;
    the line state's load transfer is the same kernel's answer."""
    stack, chains, xi, q = stack_of(CHAINS[name], seed=list(CHAINS).index(name))
    rng = np.random.default_rng([list(CHAINS).index(name), KERNELS.index(kernel)])
    for smearing in half_widths(chains[0], rng):
        transfer = check_against_the_form(stack, chains, xi, q, smearing, kernel)
        state = stack.line_state(xi, q, rotation=False, smearing=smearing, kernel=kernel)
        for mine, theirs in zip((state.load_dofs, state.G, state.dG), transfer, strict=True):
            np.testing.assert_array_equal(mine, theirs)


def test_joined_stack_reads_each_members_dof_map():
    """A joined stack (two chains of one structure, different dof maps): each member's smeared
    transfer on its own chain's dofs, as its chain's form."""
    stack, chains, xi, q = stack_of(CHAINS["fv3, galerkin-p2 arc, fv3"], seed=2)
    first = chains[0]
    beams = first.beams + [beam.translated((0.5, -2.0, 1.0)) for beam in first.beams]
    n = len(first.beams)
    ties = [(i, "end", i + 1, "start") for i in range(n - 1)]
    ties += [(n + i, "end", n + i + 1, "start") for i in range(n - 1)]
    structure = Structure(beams, ties=ties)
    a, b = BeamChain(structure, range(n)), BeamChain(structure, range(n, 2 * n))
    joined = ChainStack.joined([ChainStack([a] * len(xi)), ChainStack([b] * len(xi))])
    members = [a] * len(xi) + [b] * len(xi)
    xi2 = np.concatenate([xi, xi[::-1]])
    q2 = np.zeros((len(xi2), structure.n_dofs))
    for kernel in KERNELS:
        check_against_the_form(joined, members, xi2, q2, 0.7 * element_lengths(a).mean(), kernel)


def third_derivative_bound(chain, kernel, smearing, mass):
    """A bound on ``|G'''|`` where ``G`` is smooth, ``mass`` the least kernel mass there.

    ``G = A u``, ``u = 1 / m``.  The chain does not move with ``xi``, so ``A^(k) = (-1)^k
    int K^(k)(s - xi) H(s) ds``: the hat's ``K''`` is ``(1, -2, 1) / smearing^2`` Dirac
    masses at ``-smearing, 0, smearing``, so ``|A'| <= 2 Hmax / smearing`` (``int |K'|``),
    ``|A''| <= 4 Hmax / smearing^2``, ``|A'''| <= 4 H1 / smearing^2``, ``|m'| <= 1 /
    smearing``, ``|m''| <= 2 / smearing^2``, ``m''' = 0``; the box's ``K'`` is its two
    jumps ``-+1 / (2 smearing)``, so ``|A^(k)| <= H(k-1) / smearing`` and ``|m'| <= 1 / (2
    smearing)``, ``m'' = 0``.  ``Hmax``, ``H1`` as in ``Bounds.smeared``; ``|H''| <= H2 =
    max(16 / h_min, 8 / h_min^2)`` (the fv arm's ``|x_/xi/xi| <= 16`` spread ``/ h^2``, the
    Galerkin ``|N''| <= 8 / h^2``).  Then ``u' = -m' u^2``, ``u'' = 2 m'^2 u^3 - m'' u^2``,
    ``u''' = -6 m'^3 u^4 + 6 m' m'' u^3`` and ``G''' = A''' u + 3 A'' u' + 3 A' u'' + A
    u'''`` with ``|A| <= Hmax``."""
    h = element_lengths(chain)
    H0, H1 = max(1.0, 8 * h.max()), max(8.0, 4 / h.min())
    H2 = max(16 / h.min(), 8 / h.min() ** 2)
    if kernel == "box":
        A1, A2, A3 = H0 / smearing, H1 / smearing, H2 / smearing
        m1, m2 = 1 / (2 * smearing), 0.0
    else:
        A1, A2, A3 = 2 * H0 / smearing, 4 * H0 / smearing**2, 4 * H1 / smearing**2
        m1, m2 = 1 / smearing, 2 / smearing**2
    u = 1 / mass
    u1 = m1 * u**2
    u2 = 2 * m1**2 * u**3 + m2 * u**2
    u3 = 6 * m1**3 * u**4 + 6 * m1 * m2 * u**3
    return A3 * u + 3 * A2 * u1 + 3 * A1 * u2 + H0 * u3


def mass_near(kernel: str, smearing: float, xi: float, chain: BeamChain) -> float:
    """The kernel's mass on the chain at ``xi`` (closed form, ``kernel_mass``)."""
    lo, hi = max(xi - smearing, 0.0), min(xi + smearing, chain.length)
    return kernel_mass(kernel, smearing, lo - xi, hi - xi)


def rough_points(chain: BeamChain) -> np.ndarray:
    """Abscissae where ``H`` or ``H'`` jumps: the chain's ends, vertices and fv evaluation
    points."""
    points = [np.array([0.0, chain.length])]
    for offset, beam in zip(chain.offsets[:-1], chain.beams, strict=True):
        mesh = beam.mesh
        points.append(offset + mesh.vertex_s)
        if beam.formulation.rigid_test:
            p = evaluation_points(mesh.nodes_per_element)
            points.append(offset + mesh.abscissae(np.arange(mesh.n_elements)[:, None], p).ravel())
    return np.concatenate(points)


@pytest.mark.parametrize("name", CHAINS)
@pytest.mark.parametrize("kernel", KERNELS)
def test_derivative_is_the_central_difference(name, kernel):
    """At random abscissae whose stencil keeps the kernel's breaks off the rough points
    (``G`` smooth there, the chain's ends included), ``dG/dxi`` equals the central difference
    of ``G`` over ``+-d``, ``d = 2^-k`` near ``(3 rho / G''')^(1/3)`` with ``xi`` a multiple of
    it (the stencil's abscissae exact), within ``d^2 / 6 max|G'''|`` + ``rho / d`` + the
    derivative's own roundoff, ``rho`` that of ``G`` (``Bounds.smeared``)."""
    stack, chains, _, q = stack_of(CHAINS[name], seed=list(CHAINS).index(name))
    chain = chains[0]
    rng = np.random.default_rng([7, list(CHAINS).index(name), KERNELS.index(kernel)])
    rough, done = rough_points(chain), 0
    for smearing in np.repeat(half_widths(chain, rng), 4):
        xi = float(rng.uniform(0, chain.length))
        tol_G = Bounds(chain, xi, q[0]).smeared(smearing, kernel)[0]
        G3 = third_derivative_bound(chain, kernel, smearing, mass_near(kernel, smearing, xi, chain))
        d = 2.0 ** np.round(np.log2((3 * tol_G / G3) ** (1 / 3)))
        xi = float(np.round(xi / d) * d)
        breaks = xi + smearing * np.array([-1.0, 0.0, 1.0])
        if np.abs(breaks[:, None] - rough[None, :]).min() <= 2 * d or not d < xi < chain.length - d:
            continue
        tol_G, tol_dG = Bounds(chain, xi, q[0]).smeared(smearing, kernel)
        # the least mass over the stencil: m moves by at most |m'| <= 1 / smearing
        mass = mass_near(kernel, smearing, xi, chain) - d / smearing
        G3 = third_derivative_bound(chain, kernel, smearing, mass)
        dofs, G, dG = ChainStack([chain] * 3).transfer(
            xi + d * np.array([-1.0, 0.0, 1.0]), smearing, kernel
        )
        n = chain.structure.n_dofs
        minus, plus = scattered(dofs[0], G[0], n), scattered(dofs[2], G[2], n)
        tol = d**2 / 6 * G3 + tol_G / d + tol_dG
        np.testing.assert_allclose(
            (plus - minus) / (2 * d), scattered(dofs[1], dG[1], n), rtol=0, atol=tol
        )
        done += 1
    assert done >= 4


def test_bad_smearing_and_abscissae_name_the_item():
    stack, chains, xi, q = stack_of(CHAINS["fv2"], seed=0)
    with pytest.raises(ValueError, match="smearing must be a finite length"):
        stack.transfer(xi, -0.1, "box")
    with pytest.raises(ValueError, match="unknown smearing kernel 'tent'"):
        stack.transfer(xi, 0.1, "tent")
    with pytest.raises(ValueError, match="outside the chain"):
        stack.transfer(xi + 2 * chains[0].length, 0.1, "hat")
