"""A force and couple travelling along a chain of beams at a prescribed abscissa.

The load ``[F; M]`` acts at ``xi(t)`` on a :class:`~sliders.lines.chain.BeamChain` and reaches
the beams' dofs through their test functions there (eq. T6; smeared by a kernel of half-width
``smearing`` as a slider's reaction is): the global load vector is ``G(xi(t)) [F; M]``
gathered on the chain's dofs (:meth:`~sliders.lines.chain.BeamChain.transfer`).  It is what a
massless body driven along the chain carries without the joint: no unknowns, no Jacobian.

A :class:`MovingLoad` is a load of :class:`~sliders.solve.dynamics.Dynamics` (a function of
time); :meth:`MovingLoad.at` gives the vectors of many times at once, one compiled query of
the chain for all of them (:meth:`sliders.lines.batched.ChainStack.transfer`), which the
compiled time steps read a chunk at a time.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from fvbeam.geometry import vector3
from fvbeam.smearing import check_smearing
from sliders.joints.drives import Motion
from sliders.lines.batched import ChainStack
from sliders.lines.chain import BeamChain


class MovingLoad:
    """``force`` and ``moment`` (global axes) at the abscissa ``motion(t)`` of ``chain``
    (held at the chain's ends before and after), spread by ``smearing`` (module
    docstring)."""

    def __init__(
        self,
        chain: BeamChain,
        motion: Motion,
        force: ArrayLike = (0.0, 0.0, 0.0),
        moment: ArrayLike = (0.0, 0.0, 0.0),
        smearing: float = 0.0,
        kernel: str = "box",
        name: str = "moving load",
    ) -> None:
        if not callable(motion):
            raise ValueError(f"{name}: motion must be a motion (sliders.joints.drives)")
        self.chain, self.motion, self.name = chain, motion, name
        self.wrench = np.concatenate(
            [vector3(force, f"{name}: force"), vector3(moment, f"{name}: moment")]
        )
        on = f"chain {chain.name!r} of {name}"
        self.smearing = check_smearing(smearing, kernel, chain.length, on)
        self.kernel = kernel
        self.n_dofs = chain.structure.n_dofs
        self._stack = ChainStack([chain])
        self._stack.element_frames()

    def abscissae(self, times: ArrayLike) -> np.ndarray:
        """``xi`` at each of ``times``, held within the chain."""
        xi = np.array([self.motion(float(t))[0] for t in np.atleast_1d(times)])
        return np.clip(xi, 0.0, self.chain.length)

    def at(self, times: ArrayLike) -> np.ndarray:
        """The global load vectors at ``times``, one row each (module docstring)."""
        xi = self.abscissae(times)
        stack = self._stack.translated(np.zeros((len(xi), len(self.chain.structure.beams), 3)))
        dofs, G, _ = stack.transfer(xi, self.smearing, self.kernel)
        out = np.zeros((len(xi), self.n_dofs))
        rows = np.repeat(np.arange(len(xi)), dofs.shape[1])
        np.add.at(out, (rows, dofs.ravel()), (G @ self.wrench).ravel())
        return out

    def __call__(self, t: float) -> np.ndarray:
        """The global load vector at ``t``."""
        return self.at([t])[0]
