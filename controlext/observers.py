"""Observer objects: python-control state-space systems of the error.

An :class:`Observer` *is* a :class:`control.StateSpace` whose realisation is
its estimation-error system from noise ``w`` to error ``z̄ = Cz (x̄ − x)``::

    e' = (Ae − G Ce) e + (G Dwe − Bwe) w,      z̄ = Cze e

so ``ct.linfnorm(obs)`` is the H∞ gain γ of the papers, ``ct.poles(obs)``
gives the rate of convergence, ``ct.dcgain(obs)`` the steady-state error
per unit bias and ``ct.step_response(obs)`` the error under a constant
bias.  The runnable observer, with inputs ``[u; y]`` and output ``x̂``, is
:meth:`Observer.estimator`.

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

import numpy as np
import control as ct

from ._checks import as_matrix, as_plant
from .exceptions import DimensionError, ParameterError
from .problem import ObserverProblem
from .verify import verify_design

__all__ = ['Observer', 'LuenbergerObserver', 'CoupledObserver']


class Observer(ct.StateSpace):
    """Base class: an observer represented by its error system.

    Parameters
    ----------
    plant : control.StateSpace
        The plant ``x' = A x + B u``, ``y = C x + D u``.
    problem : ObserverProblem
        Generalised plant (noise model, copies, weights).
    G : array_like
        Coupled gain of shape ``problem.gain_shape``.
    report : DesignReport, optional
        Design report; computed (method ``'given'``) when omitted.
    name : str, optional
        System name.
    """

    def __init__(self, plant, problem, G, report=None, name=None):
        # kept as data: python-control's StateSpace does not pickle
        self._plant = dict(
            A=np.array(plant.A, dtype=float), B=np.array(plant.B, dtype=float),
            C=np.array(plant.C, dtype=float), D=np.array(plant.D, dtype=float),
            dt=plant.dt, name=plant.name, inputs=list(plant.input_labels),
            outputs=list(plant.output_labels), states=list(plant.state_labels))
        self.problem = problem
        self.G = np.array(G, dtype=float)
        N = problem.copies
        Acl, Bcl, Ccl, Dcl = problem.error_system(self.G)
        states = [f'e[{i}]' for i in range(problem.n)] if N == 1 else \
            [f'e{k + 1}[{i}]' for k in range(N) for i in range(problem.n)]
        super().__init__(Acl, Bcl, Ccl, Dcl, problem.dt, name=name,
                         inputs=_labels('w', problem.q),
                         outputs=_labels('ebar', problem.nz), states=states)
        if report is None:
            report = verify_design(problem, self.G, check=False)
        self.report = report

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
    def plant(self):
        """The plant (a new ``control.StateSpace`` at each access)."""
        d = self._plant
        return ct.ss(d['A'], d['B'], d['C'], d['D'], d['dt'], name=d['name'],
                     inputs=d['inputs'], outputs=d['outputs'],
                     states=d['states'])

    # noise model and results -------------------------------------------
    Bw = property(lambda self: self.problem.Bw, doc="Noise input matrix.")
    Dw = property(lambda self: self.problem.Dw, doc="Noise feedthrough.")
    Cz = property(lambda self: self.problem.Cz, doc="Estimated output map.")
    copies = property(lambda self: self.problem.copies,
                      doc="Number of coupled observer copies.")
    weights = property(lambda self: self.problem.weights,
                       doc="Output weights of the copies.")
    hinf = property(lambda self: self.report.hinf,
                    doc="True H∞ norm of the error system.")
    decay = property(lambda self: self.report.decay,
                     doc="Rate of convergence of the error.")

    def estimator(self, name=None):
        """The runnable observer: inputs ``[u; y]``, output ``x̄``.

        For ``N`` copies the outputs are ``xhat[i]`` (the weighted
        estimate) followed by each copy's estimate ``xhat1[i]``, ...

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
        (['u[0]', 'y[0]'], ['xhat[0]'])
        """
        prob, N, n = self.problem, self.problem.copies, self.problem.n
        plant = self.plant
        A, B, C, D = plant.A, plant.B, plant.C, plant.D
        ones = np.ones((N, 1))
        G = self.G
        Ae = np.kron(np.eye(N), A) - G @ np.kron(np.eye(N), C)
        Bu = np.kron(ones, B) - G @ np.kron(ones, D)
        By = G @ np.kron(ones, np.eye(prob.p))
        Cbar = np.kron(prob.weights.reshape(1, -1), np.eye(n))
        outputs = [f'xhat[{i}]' for i in range(n)]
        Cout = Cbar
        if N > 1:
            Cout = np.vstack([Cbar, np.eye(N * n)])
            outputs += [f'xhat{k + 1}[{i}]' for k in range(N)
                        for i in range(n)]
        states = _labels('xhat', n) if N == 1 else \
            [f'xhat{k + 1}[{i}]' for k in range(N) for i in range(n)]
        return ct.ss(Ae, np.hstack([Bu, By]), Cout,
                     np.zeros((Cout.shape[0], B.shape[1] + prob.p)),
                     plant.dt, name=name or f'{self.name}_estimator',
                     inputs=list(plant.input_labels) +
                     list(plant.output_labels),
                     outputs=outputs, states=states)


def _labels(base, count):
    return [f'{base}[{i}]' for i in range(count)]


class LuenbergerObserver(Observer):
    """Luenberger observer ``x̂' = A x̂ + B u + L (y − C x̂ − D u)``.

    Its realisation is the error system ``(A − L C, L Dw − Bw, Cz, 0)``
    from noise ``w`` to ``Cz (x̂ − x)``.

    Parameters
    ----------
    plant : control.StateSpace
        The plant.
    L : array_like
        Observer gain, ``n × p``.
    Bw, Dw, Cz : array_like, optional
        Noise model: ``x' = A x + B u + Bw w``, ``y = C x + D u + Dw w``,
        estimated output ``Cz x``.  Defaults: ``0``, ``I_p``, ``I_n``
        (measurement noise, full-state estimate).
    name : str, optional
        System name.

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-1, 1], [-1, 0]], [[0], [1]], [[1, 2]], 0)
    >>> obs = cx.LuenbergerObserver(plant, [[2], [5]])
    >>> float(round(ct.norm(obs, "inf"), 4)), round(obs.decay, 4)
    (0.4859, 1.0)
    """

    def __init__(self, plant, L, Bw=None, Dw=None, Cz=None, name=None,
                 report=None):
        A, B, C, D, dt = as_plant(plant)
        problem = ObserverProblem(A, C, Bw, Dw, Cz, copies=1, dt=dt)
        L = as_matrix(L, 'L', (problem.n, problem.p))
        super().__init__(ct.ss(plant), problem, L, report=report, name=name)

    @property
    def L(self):
        """The observer gain ``L`` (``n × p``)."""
        return self.G.copy()


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
    name : str, optional
        System name.

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

    def __init__(self, plant, Mu, weights=None, Bw=None, Dw=None, Cz=None,
                 name=None, report=None):
        A, B, C, D, dt = as_plant(plant)
        n, p = A.shape[0], C.shape[0]
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
        problem = ObserverProblem(A, C, Bw, Dw, Cz, copies=N,
                                  weights=weights, dt=dt)
        super().__init__(ct.ss(plant), problem, Mu, report=report, name=name)

    @classmethod
    def from_pair(cls, plant, K1, K2, L1, L2, **kwargs):
        """Coupled pair from the paper's gains ``K1, K2, L1, L2`` (16)."""
        A, B, C, D, dt = as_plant(plant)
        n, p = A.shape[0], C.shape[0]
        K1, K2, L1, L2 = (as_matrix(M, name, (n, p)) for M, name in
                          ((K1, 'K1'), (K2, 'K2'), (L1, 'L1'), (L2, 'L2')))
        return cls(plant, np.block([[K1, L1], [L2, K2]]), **kwargs)

    @property
    def Mu(self):
        """The coupled gain ``(N n × N p)``."""
        return self.G.copy()

    def _block(self, i, j, what):
        if self.copies != 2:
            raise AttributeError(f"{what} is defined for a coupled pair "
                                 f"(N = 2); this observer has N = "
                                 f"{self.copies}: use Mu")
        n, p = self.problem.n, self.problem.p
        return self.G[i * n:(i + 1) * n, j * p:(j + 1) * p].copy()

    K1 = property(lambda self: self._block(0, 0, 'K1'), doc="Gain K1.")
    K2 = property(lambda self: self._block(1, 1, 'K2'), doc="Gain K2.")
    L1 = property(lambda self: self._block(0, 1, 'L1'),
                  doc="Coupling gain L1 (copy 1 from copy 2's output).")
    L2 = property(lambda self: self._block(1, 0, 'L2'),
                  doc="Coupling gain L2 (copy 2 from copy 1's output).")
