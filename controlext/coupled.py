"""Coupled Luenberger observers (Li & Sanfelice): object and factory.

``N >= 2`` copies ``x̂_i' = A x̂_i + B u − Σ_j G_ij (C x̂_j + D u − y)``
with the weighted estimate ``x̄ = Σ_i c_i x̂_i``; for ``N = 2`` the gain
``Mu = [[K1, L1], [L2, K2]]`` of (16)/(27).  The averaged estimate
converges as fast as a Luenberger observer while amplifying measurement
noise less.

Examples
--------
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
>>> pair = cx.coupled_observer(plant, decay=2.5, gain_tolerance=0)
>>> bool(pair.hinf <= 0.4953)           # the nominal optimum: the paper's
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any
import numpy as np

from ._checks import as_matrix, as_plant, check_copies
from .exceptions import DimensionError, ParameterError
from .observers import Observer
from .synthesis import SynthesisOptions, plant_problem
from .synthesis.models import for_models
from .synthesis.options import synthesis_factory
from .synthesis.pipeline import design
from ._typing import Array, ArrayLike, ExecutorLike, Names, Plant

if TYPE_CHECKING:
    from .synthesis import RefineOptions, Region
    from .synthesis.verify import DesignReport

__all__ = ['CoupledObserver', 'coupled_observer']


class CoupledObserver(Observer):
    """``N >= 2`` coupled Luenberger observers with a weighted output.

    ``x̂_i' = A x̂_i + B u − Σ_j G_ij (C x̂_j + D u − y)``, estimate
    ``x̄ = Σ_i c_i x̂_i``.  For ``N = 2``, ``Mu = [[K1, L1], [L2, K2]]`` is
    the gain of Li & Sanfelice (16)/(27), and the realisation is their
    error system (28) from noise to ``Cz (x̄ − x)``.

    Parameters
    ----------
    plant : control.StateSpace
        The plant.
    Mu : array_like
        Coupled gain of shape ``(N n, N p)``.
    weights : array_like, optional
        Output weights ``c`` (length ``N``, summing to 1; default ``1/N``).
    Bw, Dw, Cz : array_like, optional
        Noise model (see :class:`LuenbergerObserver`).
    report : DesignReport, optional
        The design report (computed, method ``'given'``, when omitted).
    name : str, optional
        System name.
    inputs, outputs, states : str or list of str, optional
        Signal names of the error system (python-control's system
        keywords; see :class:`~controlext.Observer`).

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> obs = cx.CoupledObserver.from_pair(plant, 3.5198, 0.4802,
    ...                                    -8.0142, 0.2883)
    >>> round(cx.hinfnorm(obs)[0], 4)
    0.4953
    """

    def __init__(self, plant: Plant, Mu: ArrayLike,
                 weights: ArrayLike | None = None, Bw: ArrayLike | None = None,
                 Dw: ArrayLike | None = None, Cz: ArrayLike | None = None,
                 name: str | None = None, report: DesignReport | None = None,
                 *, inputs: Names = None, outputs: Names = None,
                 states: Names = None) -> None:
        one = plant_problem(plant, Bw, Dw, Cz)
        n, p = one.n, one.p
        Mu = as_matrix(Mu, 'Mu', (None, None))
        N = Mu.shape[0] // n
        if Mu.shape[0] % n or Mu.shape[1] != N * p or N < 1:
            raise DimensionError(
                f"Mu must have shape (N·n, N·p) = (N·{n}, N·{p}) for N "
                f"coupled copies; found {Mu.shape}")
        if N < 2:
            raise ParameterError(
                "a coupled observer needs at least 2 copies; found Mu of "
                f"shape {Mu.shape}, i.e. 1 copy: use LuenbergerObserver")
        problem = one.replace(copies=N, weights=weights)
        super().__init__(problem, Mu, report=report, name=name,
                         inputs=inputs, outputs=outputs, states=states)

    @classmethod
    def from_pair(cls, plant: Plant, K1: ArrayLike, K2: ArrayLike,
                  L1: ArrayLike, L2: ArrayLike,
                  **kwargs: Any) -> CoupledObserver:
        """Coupled pair from the paper's gains ``K1, K2, L1, L2`` (16)."""
        A, B, C, D, dt = as_plant(plant)
        n, p = A.shape[0], C.shape[0]
        K1, K2, L1, L2 = (as_matrix(M, name, (n, p)) for M, name in
                          ((K1, 'K1'), (K2, 'K2'), (L1, 'L1'), (L2, 'L2')))
        return cls(plant, np.block([[K1, L1], [L2, K2]]), **kwargs)

    @property
    def Mu(self) -> Array:
        """The coupled gain ``(N n × N p)``."""
        return self.G

    def _block(self, i, j, what):
        if self.copies != 2:
            raise AttributeError(f"{what} is defined for a coupled pair "
                                 f"(N = 2); this observer has N = "
                                 f"{self.copies}: use Mu")
        n, p = self.problem.n, self.problem.p
        return self.G[i * n:(i + 1) * n, j * p:(j + 1) * p]

    @property
    def K1(self) -> Array:
        """Gain K1."""
        return self._block(0, 0, 'K1')

    @property
    def K2(self) -> Array:
        """Gain K2."""
        return self._block(1, 1, 'K2')

    @property
    def L1(self) -> Array:
        """Coupling gain L1 (copy 1 from copy 2's output)."""
        return self._block(0, 1, 'L1')

    @property
    def L2(self) -> Array:
        """Coupling gain L2 (copy 2 from copy 1's output)."""
        return self._block(1, 0, 'L2')

    @property
    def L(self) -> Array:
        """Not defined: a coupled observer has no single Luenberger gain."""
        raise AttributeError(
            "a CoupledObserver has no single gain L: its gain is the block "
            "matrix Mu (obs.Mu, of shape N n x N p)"
            + ("; a pair's blocks are obs.K1, obs.L1, obs.L2, obs.K2"
               if self.copies == 2 else ""))



@synthesis_factory
def coupled_observer(plant: Plant, decay: float | None = None, copies: int = 2,
                     weights: ArrayLike | None = None,
                     Bw: ArrayLike | None = None, Dw: ArrayLike | None = None,
                     Cz: ArrayLike | None = None, *,
                     region: Region | None = None, method: str = 'auto',
                     refine: bool = True, margin: float = 1.02,
                     solver: str | None = None,
                     solver_options: dict[str, Any] | None = None,
                     seed: int = 0,
                     refine_options: RefineOptions | dict[str, Any] | None = None,
                     executor: ExecutorLike = None,
                     options: SynthesisOptions | None = None,
                     max_gain: float | str | None = 'auto',
                     objective: str = 'hinf', max_hinf: float | None = None,
                     max_h2: float | None = None,
                     settling_time: float | None = None,
                     gain_tolerance: float | None = None,
                     name: str | None = None, inputs: Names = None,
                     outputs: Names = None,
                     states: Names = None) -> CoupledObserver:
    """Coupled Luenberger observers minimising the H∞ norm (Li & Sanfelice).

    A convex stage gives a certified design; refinement then minimises the
    true H∞ norm of the error system under the pole-region constraint from
    several starts: the convex design, the Luenberger-equivalent design
    ``K_i = L0``, ``L_i = 0`` (with ``L0`` the refined one-copy design of
    the same problem, as :func:`hinf_observer` returns it), and seeded
    perturbations of both.  The result is therefore never worse
    than the best Luenberger observer found for the same region.  With
    three or more copies and equal weights, the design of ``copies − 1``
    (made the same way) is grown to ``copies`` — the last copy tracks the
    others' average (:meth:`ObserverProblem.grow
    <controlext.synthesis.ObserverProblem.grow>`) — and is a candidate
    too, so more copies are never worse (within the 0.1 % to which
    designs count as equal).  Under a gain tolerance (the default) the
    grown design is refined under it from there, since the grown gain
    itself rarely meets it.

    The convex stage is, by default (``method='auto'``), the n-state
    Luenberger LMI embedded as ``K_i = L0``, ``L_i = 0``: it has the same γ
    as the common-Lyapunov coupled LMI of Theorem 3.10 in every case
    measured, and its solve time grows as about ``n^3.7`` instead of
    ``n^4.5``.  ``method='lmi'`` solves Theorem 3.10 (``N n`` states).

    Parameters
    ----------
    plant : control.StateSpace or sequence of control.StateSpace
        Detectable plant, or several models of it (equal sizes, one
        timebase; the first is the nominal one): one gain is designed for
        all, the worst case over the models minimised, the region and
        every limit held on each (:attr:`Observer.models`).
    decay : float, optional
        Required rate of convergence (every error pole has
        ``Re s <= -decay``); shorthand for ``region=cx.HalfPlane(decay)``.
    copies : int, optional
        Number of coupled copies ``N >= 2``.
    weights : array_like, optional
        Output weights (length ``N``, summing to 1; default ``1/N``).
    Bw, Dw, Cz : array_like, optional
        Noise model (see :class:`LuenbergerObserver`).
    region : Region, optional
        Pole region.
    method : {'auto', 'lmi', 'riccati', 'modal'}, optional
        Convex stage: the embedded n-state design of :func:`hinf_observer`
        with the same ``method`` (``'auto'``, ``'riccati'``, ``'modal'``),
        or the coupled LMI of Theorem 3.10 (``'lmi'``).
    refine : bool, optional
        Run the refinement stage (default).  Without it the result is the
        convex (conservative) design.
    margin, solver, solver_options, seed, refine_options, name : optional
        As for :func:`hinf_observer`.
    executor : concurrent.futures.Executor, optional
        Runs the refinement's starts in parallel (results do not depend on
        it).
    max_gain : float, 'auto' or None, optional
        Bound on the gain's spectral norm ``‖G‖₂`` in the plant's units,
        held by refinement and verified; ``'auto'`` (default) bounds it at
        1e6 times the plant's scale and warns when it binds, ``None``
        lifts it (:class:`~controlext.synthesis.SynthesisOptions`).
    objective, max_hinf, max_h2 : optional
        The norm minimised and a bound on the other (the mixed H2/H∞
        design), as for :func:`hinf_observer`.
    settling_time, gain_tolerance : float, optional
        A settling time of the averaged error and a certified tolerance
        of relative gain errors, as for :func:`hinf_observer`.
    options : SynthesisOptions, optional
        Every tunable of the engine (``lmi_max_states``, ``modal_guard``,
        …); the keywords above override it where they differ from their
        defaults.
    inputs, outputs, states : str or list of str, optional
        Signal names of the error system (python-control's system
        keywords; see :class:`~controlext.Observer`).

    Returns
    -------
    CoupledObserver

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> obs = cx.coupled_observer(plant, decay=2.5)   # robust decay
    >>> bool(obs.hinf <= 0.4953 * 1.002), bool(obs.decay >= 2.5 - 1e-6)
    (True, True)
    """
    copies = check_copies(copies, 2)
    problem = for_models(
        plant, lambda P, **noise: plant_problem(P, copies=copies,
                                                weights=weights, **noise),
        Bw=Bw, Dw=Dw, Cz=Cz)
    return design(CoupledObserver, problem, options, decay=decay,
                  region=region, system=dict(name=name, inputs=inputs,
                                             outputs=outputs, states=states))
