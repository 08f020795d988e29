"""Observer objects: python-control state-space systems of the error.

An :class:`Observer` *is* a :class:`control.StateSpace` whose realisation is
its estimation-error system from noise ``w`` to error ``z̄ = Cz (x̄ − x)``::

    e' = (Ae − G Ce) e + (G Dwe − Bwe) w,      z̄ = Cze e

so ``ct.linfnorm(obs)`` is the H∞ gain γ of the papers, ``ct.poles(obs)``
gives the rate of convergence, ``ct.dcgain(obs)`` the steady-state error
per unit bias and ``ct.step_response(obs)`` the error under a constant
bias.  The runnable observer, with inputs ``[y; u]`` and output ``x̂``, is
:meth:`Observer.estimator`: pass ``estimator=obs.estimator()``, not
``obs``, to ``ct.create_statefbk_iosystem`` (which refuses the error
system with an :class:`~controlext.exceptions.ArgumentError` saying so).

The object and its estimator come from one
:class:`~controlext.synthesis.ObserverProblem` (the generalised plant the
design was made on), so they cannot disagree; this module knows no
observer kind (the kinds live in ``luenberger.py``, ``coupled.py`` and
``gi.py``).

python-control's algebra (``+``, ``*``, ``feedback``, indexing, ``sample``,
``minreal``) returns plain ``StateSpace`` objects; ``copy()``,
``copy.deepcopy`` and ``pickle`` keep the class and its attributes.

Examples
--------
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
>>> obs = cx.LuenbergerObserver(plant, [[2.0]])
>>> float(round(ct.linfnorm(obs)[0], 4)), ct.poles(obs).real.tolist()
(0.8, [-2.5])
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Self
import numpy as np
import control as ct

from ._checks import as_plant, check_name, check_system
from .exceptions import ArgumentError, DimensionError
from ._text import table_row
from .synthesis.floor import filter_floor
from .synthesis.problem import plant_problem
from .synthesis.tradeoff import Tradeoff, tradeoff_of
from .synthesis.verify import verify_design
from ._typing import Array, ArrayLike, Names

if TYPE_CHECKING:
    from .synthesis import ObserverProblem
    from .synthesis.verify import DesignReport

__all__ = ['Observer']


class Observer(ct.StateSpace):
    """Base class: an observer represented by its error system.

    Parameters
    ----------
    problem : ObserverProblem
        The generalised plant the observer was designed on (plant, noise
        model, copies, weights, the estimator's measurement maps).
    G : array_like
        Coupled gain of shape ``problem.gain_shape``.
    report : DesignReport, optional
        Design report; computed (method ``'given'``) when omitted.
    name : str, optional
        System name.
    inputs, outputs, states : str or list of str, optional
        Signal names of the error system (python-control's system
        keywords): a base name or one name per signal.  Defaults: noise
        ``w[i]``, weighted error ``ebar[i]``, errors ``e[i]`` (``e<k>[i]``
        for copy ``k``).

    Subclasses give the user-facing constructors (from the plant and the
    gains) and build their problem; factories build the object from the
    problem they designed on with :meth:`from_problem`.
    """

    def __init__(self, problem: ObserverProblem, G: ArrayLike,
                 report: DesignReport | None = None, name: str | None = None,
                 *, inputs: Names = None, outputs: Names = None,
                 states: Names = None) -> None:
        check_system(name, inputs, outputs, states)
        members = problem.members
        # a design for several plant models is the nominal model's error
        # system; the others are kept for `models`
        problem = members[0]
        self._models = members if len(members) > 1 else None
        signals = problem.error_signals(inputs, outputs, states)
        self.problem = problem
        self._G = np.array(G, dtype=float)
        self._G.setflags(write=False)
        Acl, Bcl, Ccl, Dcl = problem.error_system(self._G)
        super().__init__(Acl, Bcl, Ccl, Dcl, problem.dt, name=name,
                         **signals)
        if report is None:
            report = verify_design(problem, self._G, check=False)
        self.report = report

    # python-control's state-feedback builder reads an estimator's state
    # labels first: an observer there is the error system passed where
    # the runnable estimator belongs, which would build a wrong loop
    @property
    def state_labels(self) -> list[str]:
        """The error system's state names (python-control's property)."""
        if sys._getframe(1).f_code.co_name == 'create_statefbk_iosystem':
            raise ArgumentError(
                f"estimator={type(self).__name__} is the estimation-error "
                "system (noise -> error), not a runnable estimator: pass "
                "estimator=obs.estimator() (inputs [y; u] with the plant's "
                "labels, output the estimate)")
        return list(self.state_index.keys())

    @state_labels.setter
    def state_labels(self, names):
        ct.InputOutputSystem.state_labels.fset(self, names)

    @classmethod
    def from_problem(cls, problem: ObserverProblem, G: ArrayLike,
                     report: DesignReport | None = None,
                     name: str | None = None, **signals: Names) -> Self:
        """The observer of gain ``G`` designed on ``problem``
        (``signals``: the system keywords ``inputs``, ``outputs``,
        ``states``)."""
        obs = cls.__new__(cls)
        Observer.__init__(obs, problem, G, report=report, name=name,
                          **signals)
        return obs

    # a readable design ---------------------------------------------------

    def _summary(self):
        prob = self.problem
        time_ = 'discrete' if prob.dt else 'continuous'
        copies = f"{prob.copies} coupled copies" if prob.copies > 1 else \
            "one copy"
        return (f"{type(self).__name__} {self.name!r}: {copies} on a "
                f"{prob.nx}-state, {prob.p}-output {time_}-time plant")

    def __repr__(self):
        # python-control's convention: config.defaults['iosys.repr_format']
        # chooses 'info' (a summary), 'eval' (an expression that rebuilds
        # the system: here the error system) or 'latex'
        fmt = ct.config.defaults.get('iosys.repr_format', 'info')
        if fmt == 'info':
            return self._repr_info_()
        return super().__repr__()

    def _repr_info_(self):
        return (f"<{type(self).__name__} {self.name!r}: copies={self.copies}"
                f", states={self.problem.nx}, outputs={self.problem.p}, "
                f"γ={self.hinf:.6g}, decay={self.decay:.6g}, "
                f"stage={self.report.stage!r}>")

    def __str__(self):
        # enough digits that the printed gain keeps the promised region
        digits = 4 if self.report.tradeoff is None else \
            max(4, self.report.tradeoff.digits)
        gain = _matrix_text(self._G, digits)
        trade = [] if self.report.tradeoff is None else \
            [str(self.report.tradeoff)]
        system = ct.StateSpace.__str__(self)
        return '\n'.join([self._summary(), str(self.report),
                          table_row('gain norm ‖G‖',
                                    f"{np.linalg.norm(self._G, 2):.6g}")] +
                         trade + ["G =", gain, "",
                          "error system (noise w -> estimation error):",
                          system])

    @property
    def tradeoff(self) -> Tradeoff:
        """What the design trades besides γ: the floor γ∞*, the H2 norm,
        the transient, the gain norm and the decay's sensitivity to gain
        errors (:mod:`controlext.synthesis.tradeoff`; measured by every
        factory, computed here on first use for a given gain)."""
        if self.report.tradeoff is None:
            self.report.tradeoff = tradeoff_of(
                self.problem, self._G, self.name,
                floor=filter_floor(self.problem), region=self.report.region,
                hinf=self.hinf)
        return self.report.tradeoff

    def _repr_html_(self):
        rows = [('γ (H∞, noise → error)', f"{self.hinf:.6g}"),
                ('decay rate', f"{self.decay:.6g}"),
                ('gain norm ‖G‖', f"{np.linalg.norm(self._G, 2):.6g}"),
                ('stage', f"{self.report.stage} ({self.report.method})")]
        if self.report.gamma_bound is not None:
            rows.insert(1, ('convex stage certified',
                            f"{self.report.gamma_bound:.6g}"))
        body = ''.join(f"<tr><td>{k}</td><td>{v}</td></tr>" for k, v in rows)
        gain = np.array2string(self._G, precision=4, suppress_small=True)
        return (f"<p><b>{self._summary()}</b></p><table>{body}</table>"
                f"<pre>G = {gain}</pre>")

    # pickling: python-control keeps two lambdas in the instance dictionary
    def __getstate__(self):
        state = self.__dict__.copy()
        state.pop('updfcn', None)
        state.pop('outfcn', None)
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.updfcn = lambda t, x, u, params: \
            self.A @ np.atleast_1d(x) + self.B @ np.atleast_1d(u)
        self.outfcn = lambda t, x, u, params: \
            self.C @ np.atleast_1d(x) + self.D @ np.atleast_1d(u)

    @property
    def plant(self) -> ct.StateSpace:
        """The plant (a new ``control.StateSpace`` at each access)."""
        prob, n = self.problem, self.problem.nx
        sig = prob.signals
        return ct.ss(prob.A[:n, :n], prob.B[:n], prob.C[:, :n], prob.D,
                     prob.dt, name=sig.get('name'),
                     inputs=sig.get('inputs', prob.nu),
                     outputs=sig.get('outputs', prob.p),
                     states=sig.get('states', n))

    # noise model and results -------------------------------------------
    @property
    def G(self) -> Array:
        """The coupled gain (a copy)."""
        return self._G.copy()

    @property
    def Bw(self) -> Array:
        """Noise input matrix of the error system (a copy)."""
        return self.problem.Bw.copy()

    @property
    def Dw(self) -> Array:
        """Noise feedthrough of the error system (a copy)."""
        return self.problem.Dw.copy()

    @property
    def Cz(self) -> Array:
        """Estimated output map (a copy)."""
        return self.problem.Cz.copy()

    @property
    def copies(self) -> int:
        """Number of coupled observer copies."""
        return self.problem.copies

    @property
    def weights(self) -> Array:
        """Output weights of the copies."""
        return self.problem.weights.copy()

    @property
    def hinf(self) -> float:
        """True H∞ norm of the error system (of a design for several
        plant models: the worst case over them)."""
        return self.report.hinf

    @property
    def decay(self) -> float:
        """Rate of convergence of the error (of a design for several plant
        models: the slowest over them)."""
        return self.report.decay

    @property
    def models(self) -> list[Self]:
        """The observer on each plant model it was designed for, the
        nominal first (its error system is this one's): observers of this
        class, one per model, each with that model's report (``[self]``
        for a design on one model)."""
        if self._models is None:
            return [self]
        return [type(self).from_problem(
            member, self._G, report=verify_design(
                member, self._G, self.report.region, check=False,
                criteria=self.report.criteria),
            name=f'{self.name}[{k}]')
            for k, member in enumerate(self._models)]

    def on(self, plant: ct.StateSpace, name: str | None = None) -> Self:
        """This observer's gain on another plant of the same sizes and
        timebase: the observer (error system and estimator) it makes
        there, with its report, to check a design on a plant it was not
        designed for.

        Parameters
        ----------
        plant : control.StateSpace
            A plant with the observer's state, output and input counts
            and timebase (the noise model, copies and weights are the
            observer's).
        name : str, optional
            System name (default: the observer's name + ``'_on'``).

        Returns
        -------
        Observer
            Of this observer's class, with its report on ``plant``.

        Examples
        --------
        >>> import control as ct
        >>> import controlext as cx
        >>> obs = cx.LuenbergerObserver(ct.ss([[-0.5]], [[1.0]], [[1.0]], 0),
        ...                             [[2.0]])
        >>> round(obs.on(ct.ss([[-1.5]], [[1.0]], [[1.0]], 0)).decay, 4)
        3.5
        """
        check_name(name)
        A, B, C, _, dt = as_plant(plant)
        prob = self.problem
        for what, a, b in (('states', prob.nx, A.shape[0]),
                           ('measurements', prob.p, C.shape[0]),
                           ('inputs', prob.nu, B.shape[1])):
            if a != b:
                raise DimensionError(
                    f"plant must have the observer's {what} ({a}); found "
                    f"{b}")
        if dt != prob.dt:
            raise DimensionError(
                f"plant must have the observer's timebase dt={prob.dt}; "
                f"found dt={dt}")
        other = self._problem_of(plant)
        report = verify_design(other, self._G, self.report.region,
                               check=False, criteria=self.report.criteria)
        return type(self).from_problem(other, self._G, report=report,
                                       name=name or f'{self.name}_on')

    def _problem_of(self, plant):
        """The problem of this observer's kind on another plant, with the
        same noise model, copies and weights."""
        prob = self.problem
        return plant_problem(plant, prob.Bw, prob.Dw, prob.Cz,
                             copies=prob.copies, weights=prob.weights)


    def estimator(self, name: str | None = None, copy_outputs: bool = False,
                  disturbance: bool = False) -> ct.StateSpace:
        """The runnable observer: inputs ``[y; u]``, output ``x̂``.

        The inputs carry the plant's own output and input labels, so
        ``ct.interconnect`` and ``ct.create_statefbk_iosystem(plant, K,
        estimator=obs.estimator())`` connect it by name; the outputs are
        the estimate ``xhat[i]`` (the weighted average of the copies).

        Parameters
        ----------
        name : str, optional
            System name (default: the observer's name + ``'_estimator'``).
        copy_outputs : bool, optional
            Also output every copy's estimate ``xhat<k>[i]``.
        disturbance : bool, optional
            Also output the disturbance estimate ``dhat[i]`` (observers
            that estimate one: the augmented GI observer).

        Returns
        -------
        control.StateSpace

        Examples
        --------
        >>> import control as ct
        >>> import controlext as cx
        >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
        >>> est = cx.LuenbergerObserver(plant, [[2.0]]).estimator()
        >>> est.input_labels, est.output_labels
        (['y[0]', 'u[0]'], ['xhat[0]'])
        """
        check_name(name)
        prob = self.problem
        N, n, m = prob.copies, prob.nx, prob.n
        extra = prob.extra_outputs
        A, Bu, By, Cout = prob.estimator_matrices(
            self._G, copy_outputs=copy_outputs)
        keep = list(range(n))
        outputs = _labels('xhat', n)
        if extra is not None:
            if disturbance:
                keep += list(range(n, n + extra[1].shape[0]))
                outputs += _labels(extra[0], extra[1].shape[0])
            start = n + extra[1].shape[0]
        else:
            start = n
        if copy_outputs:
            keep += list(range(start, start + N * n))
            outputs += [f'xhat{k + 1}[{i}]' for k in range(N)
                        for i in range(n)]
        Cout = Cout[keep]
        per_copy = [('xhat', i) for i in range(n)] + \
            [('alphahat', i) for i in range(m - n)]
        states = [f'{base}[{i}]' for base, i in per_copy] if N == 1 else \
            [f'{base}{k + 1}[{i}]' for k in range(N) for base, i in per_copy]
        plant = self.plant
        return ct.ss(A, np.hstack([By, Bu]), Cout,
                     np.zeros((Cout.shape[0], prob.p + prob.nu)), prob.dt,
                     name=name or f'{self.name}_estimator',
                     inputs=list(plant.output_labels) +
                     list(plant.input_labels),
                     outputs=outputs, states=states)


def _labels(base, count):
    return [f'{base}[{i}]' for i in range(count)]


def _matrix_text(M, digits):
    """A matrix in aligned columns, ``digits`` significant digits, no
    ``-0``."""
    M = np.asarray(M, dtype=float) + 0.0
    if digits > 6:
        cells = [[f"{x: .{digits - 1}e}" for x in row] for row in M]
    else:
        cells = [[f"{x: .{digits}g}" for x in row] for row in M]
    cells = [[c.replace('-0 ', ' 0 ') if c.strip() in ('-0', '-0.0') else c
              for c in row] for row in cells]
    width = max((len(c) for row in cells for c in row), default=0)
    return '\n'.join('  '.join(c.rjust(width) for c in row)
                     for row in cells)
