"""Pole regions for the estimation-error dynamics.

A region is an LMI region in the sense of Chilali and Gahinet: the set
``{z : L + M z + Mᵀ z̄ < 0}`` of the complex plane, given by its
*characteristic matrices* ``L = Lᵀ`` and ``M``.  The matrix ``Acl`` has all
its eigenvalues in the region if and only if there is ``X = Xᵀ > 0`` with

    L ⊗ X + M ⊗ Zᵀ + Mᵀ ⊗ Z < 0,   Z = X Acl,

which is linear in ``(X, Y)`` for ``Z = X Ae − Y Ce``; the engine in
:mod:`controlext.synthesis.lmi` builds that constraint from :meth:`Region.blocks`.
Regions also give the scalar *margins* that the refinement stage and the
verification use: ``g(λ) ≤ 0`` for every eigenvalue ``λ`` in the region.

Examples
--------
>>> import controlext as cx
>>> region = cx.HalfPlane(1.0)
>>> region.contains([-1.5, -1.0 + 2j])
True
>>> region.contains([-0.5])
False
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any
from functools import partial

import numpy as np

from .._checks import check_number, sample_step
from ..exceptions import ArgumentError, ParameterError, RegionError
from .._typing import Array, ArrayLike, BoolArray

__all__ = ['Region', 'HalfPlane', 'Disk', 'Sector', 'region_for', 'check_decay']

_TOL = 1e-9


class Region:
    """An intersection of LMI regions (base class).

    Subclasses define ``_parts``: a list of ``(L, M, margin, grad,
    boundary, edge)`` with ``margin(λ) -> float`` (``<= 0`` inside),
    ``grad(λ) -> (dg/dRe, dg/dIm)``, ``boundary(extent, num) -> [curves]``
    and ``edge`` the part's boundary as a map of a stability boundary
    (:meth:`edges`), or None.

    Parameters
    ----------
    parts : sequence
        The parts ``(L, M, margin, grad, boundary, edge)`` whose
        intersection the region is.
    label : str
        What ``repr`` shows.
    """

    #: 'continuous', 'discrete' or 'any': the time domain the region fits
    domain = 'any'

    def __init__(self, parts: Sequence[Any], label: str) -> None:
        self._parts = list(parts)
        self._label = label

    def __and__(self, other):
        if not isinstance(other, Region):
            raise ArgumentError(
                f"a region intersects only another region (HalfPlane, "
                f"Disk, Sector or their intersection); found "
                f"{type(other).__name__} {other!r}")
        domains = {self.domain, other.domain} - {'any'}
        if len(domains) > 1:
            raise ParameterError("cannot intersect a continuous-time region "
                             "with a discrete-time one")
        out = Region(self._parts + other._parts,
                     f"{self._label} & {other._label}")
        out.domain = domains.pop() if domains else 'any'
        return out

    def __rand__(self, other):
        return self & other

    def __repr__(self):
        return self._label

    __str__ = __repr__

    def blocks(self) -> list[Any]:
        """Characteristic matrices ``[(L, M), ...]`` of each part."""
        return [(np.atleast_2d(part[0]), np.atleast_2d(part[1]))
                for part in self._parts]

    def edges(self) -> list[tuple[str, float, float]]:
        """Each part's boundary as an affine image of a stability boundary:
        ``('plane', a, 1)`` for the line ``Re s = a`` (the imaginary axis
        shifted by ``a``) and ``('circle', c, r)`` for ``|z − c| = r``.
        The largest resolvent norm on a boundary is then an H∞ norm of a
        shifted (or shifted and scaled) system
        (:mod:`~controlext.synthesis.limits`).

        Raises
        ------
        ArgumentError
            For a part whose boundary is no such image (a sector's rays).
        """
        out = []
        for part in self._parts:
            if part[5] is None:
                raise ArgumentError(
                    f"{self} has a part whose boundary is not a line "
                    "Re s = a or a circle; a bound along it (gain_"
                    "tolerance=) is held for half-planes and disks only")
            out.append(part[5])
        return out

    def margins(self, eigs: ArrayLike) -> Array:
        """Array ``(len(eigs), parts)`` of ``g(λ)``; ``<= 0`` inside."""
        lams: Array = np.atleast_1d(np.asarray(eigs, dtype=complex)).ravel()
        # the parts' margins are elementwise numpy expressions
        out = np.empty((lams.size, len(self._parts)))
        for k, part in enumerate(self._parts):
            out[:, k] = part[2](lams)
        return out

    def margin_gradients(self, eigs: ArrayLike) -> Array:
        """Array ``(len(eigs), parts, 2)`` of ``(dg/dRe λ, dg/dIm λ)``."""
        lams: Array = np.atleast_1d(np.asarray(eigs, dtype=complex))
        return np.array([[part[3](lam) for part in self._parts]
                         for lam in lams]).reshape(len(lams), -1, 2)

    def worst_margin(self, eigs: ArrayLike) -> float:
        """Largest margin over eigenvalues and parts (``<= 0`` inside)."""
        return float(np.max(self.margins(eigs)))

    def stable_interval(self, dt: float | bool = 0) -> tuple[float,
                        float] | None:
        """The real points of the region where an error pole is stable:
        the interval ``(a, b)`` (``a`` may be very negative for unbounded
        continuous-time regions), or None if the region has no stable
        point at all.

        An LMI region is convex and symmetric about the real axis, so it
        has a stable point if and only if it has a real one: the worst
        margin along the real axis (with ``Re s < 0``, or ``|z| < 1``
        added) is convex, and its minimum decides the question.

        Examples
        --------
        >>> import controlext as cx
        >>> a, b = cx.Disk(0.5, center=-1.0).stable_interval()
        >>> round(a, 6), round(b, 6)
        (-1.5, -0.5)
        >>> (cx.HalfPlane(2.0) & cx.Disk(1.0)).stable_interval() is None
        True
        """
        from scipy.optimize import minimize_scalar
        stability = (lambda x: abs(x) - 1.0) if dt else (lambda x: x)

        def worst(x):
            return max(self.worst_margin([x]), stability(x))

        size = 1.0 + sum(abs(float(v)) for part in self._parts
                         for v in np.ravel(part[0]))
        lo, hi = (-1.0, 1.0) if dt else (-1e6 * size, 0.0)
        res = minimize_scalar(worst, bounds=(lo, hi), method='bounded',
                              options={'xatol': 1e-12 * size})
        x = float(res.x)
        if not worst(x) < -_TOL:
            return None

        def edge(outside):
            inside = x
            for _ in range(200):
                mid = 0.5 * (inside + outside)
                if worst(mid) < -_TOL:
                    inside = mid
                else:
                    outside = mid
            return inside

        return edge(lo), edge(hi)

    def contains(self, eigs: ArrayLike, tol: float = _TOL) -> bool:
        """True if every eigenvalue lies in the region (to ``tol``)."""
        return self.worst_margin(eigs) <= tol

    def inside(self, points: ArrayLike) -> BoolArray:
        """Boolean array: which of ``points`` (complex) lie in the region.

        Vectorised over any array shape (for shading a grid).
        """
        pts = np.asarray(points, dtype=complex)
        flat = pts.ravel()
        if flat.size == 0:
            return np.zeros(pts.shape, dtype=bool)
        return (self.margins(flat).max(axis=1) <= _TOL).reshape(pts.shape)

    def boundary(self, extent: tuple[float, float, float, float], num: int = 400) -> list[Array]:
        """Boundary curves of the region's parts inside ``extent``.

        Parameters
        ----------
        extent : (re_min, re_max, im_min, im_max)
            Window of the complex plane.
        num : int
            Points per curve.

        Returns
        -------
        list of ndarray
            Complex points along each part's boundary (for plotting).
        """
        return [curve for part in self._parts
                for curve in part[4](extent, num)]


class HalfPlane(Region):
    """The half-plane ``Re s <= -decay`` (continuous time).

    Parameters
    ----------
    decay : float
        Required rate of decay ``σ >= 0`` of the estimation error.

    Examples
    --------
    >>> import controlext as cx
    >>> cx.HalfPlane(2.5).contains([-2.5, -3 + 1j])
    True
    """

    domain = 'continuous'

    def __init__(self, decay: float) -> None:
        decay = check_number(decay, 'decay')
        if decay < 0:
            raise ParameterError(f"decay must be a finite number >= 0; "
                                 f"found {decay}")
        self.decay = decay
        super().__init__(
            [(2 * decay, 1.0, partial(_half_margin, decay), _half_grad,
              partial(_half_boundary, decay), ('plane', -decay, 1.0))],
            f"HalfPlane(decay={decay:g})")


class Disk(Region):
    """The disk ``|s - center| <= radius`` (continuous or discrete time).

    ``domain='discrete'`` marks a disk meant for the z-plane (and
    ``'continuous'`` one for the s-plane), so that giving it to a plant of
    the other kind is an error; the default fits either.

    Parameters
    ----------
    radius : float
        Radius, ``> 0``.
    center : float, optional
        Centre on the real axis (default 0).
    domain : {'any', 'continuous', 'discrete'}, optional
        The time domain the disk is meant for.

    Examples
    --------
    >>> import controlext as cx
    >>> cx.Disk(0.9).contains([0.5 + 0.5j])
    True
    """

    def __init__(self, radius: float, center: float = 0.0,
                 domain: str = 'any') -> None:
        radius, center = check_number(radius, 'radius'), check_number(center, 'center')
        if radius <= 0:
            raise ParameterError(f"radius must be > 0; found {radius}")
        if domain not in ('any', 'continuous', 'discrete'):
            raise ParameterError("domain must be 'any', 'continuous' or "
                                 f"'discrete'; found {domain!r}")
        self.radius, self.center, self.domain = radius, center, domain
        super().__init__(
            [(np.array([[-radius, -center], [-center, -radius]]),
              np.array([[0.0, 1.0], [0.0, 0.0]]),
              partial(_disk_margin, radius, center),
              partial(_disk_grad, center),
              partial(_disk_boundary, radius, center),
              ('circle', center, radius))],
            f"Disk(radius={radius:g}, center={center:g})")


class Sector(Region):
    """Damping ratio at least ``damping`` (continuous time): the cone
    ``|Im s| <= -Re s · tan(acos(damping))``.

    Parameters
    ----------
    damping : float
        Least damping ratio, in ``(0, 1]``.

    Examples
    --------
    >>> import controlext as cx
    >>> cx.Sector(0.5).contains([-1 + 1j])
    True
    """

    domain = 'continuous'

    def __init__(self, damping: float) -> None:
        damping = check_number(damping, 'damping')
        if not 0 <= damping < 1:
            raise ParameterError(f"damping must lie in [0, 1); found "
                                 f"{damping}")
        self.damping = damping
        th = np.arccos(damping)
        s, c = np.sin(th), np.cos(th)
        super().__init__(
            [(np.zeros((2, 2)), np.array([[s, c], [-c, s]]),
              partial(_sector_margin, s, c), partial(_sector_grad, s, c),
              partial(_sector_boundary, th), None)],
            f"Sector(damping={damping:g})")


# margins, gradients and boundaries of the parts (module level so that
# regions pickle, e.g. for a ProcessPoolExecutor)

def _half_margin(decay, z):
    return z.real + decay


def _half_grad(z):
    return (1.0, 0.0)


def _half_boundary(decay, extent, num):
    return [-decay + 1j * np.linspace(extent[2], extent[3], num)]


def _disk_margin(radius, center, z):
    return abs(z - center) - radius


def _disk_grad(center, z):
    d = z - center
    r = abs(d)
    return (1.0, 0.0) if r == 0 else (d.real / r, d.imag / r)


def _disk_boundary(radius, center, extent, num):
    return [center + radius * np.exp(1j * np.linspace(0, 2 * np.pi, num))]


def _sector_margin(s, c, z):
    return s * z.real + c * abs(z.imag)


def _sector_grad(s, c, z):
    return (s, c * np.sign(z.imag))


def _sector_boundary(th, extent, num):
    r = np.linspace(0, 2 * max(abs(e) for e in extent), num)
    return [r * -np.exp(1j * th), r * -np.exp(-1j * th)]


def check_decay(decay: Any) -> float | None:
    """A decay rate ``σ > 0`` (None: no decay asked for).

    Examples
    --------
    >>> from controlext.synthesis.regions import check_decay
    >>> check_decay(2)
    2.0
    """
    if decay is not None and np.ndim(decay) > 0 and \
            not isinstance(decay, str):
        raise ArgumentError(
            f"decay must be a number (the rate sigma of Re s <= -sigma); "
            f"found an array of shape {np.shape(decay)}.  The noise model "
            "is Bw=, Dw= (not lqe's QN, RN): pass Bw=G for process noise "
            "entering through G, Dw= for how the noise enters the "
            "measurements")
    decay = check_number(decay, 'decay', low=0, optional=True)
    if decay == 0:
        raise ParameterError(
            "decay must be > 0; found 0, which asks for no more than the "
            "stability every design has: omit decay= for that")
    return decay


def region_for(decay: float | None = None, region: Region | None = None,
               dt: float | bool = 0) -> Region | None:
    """The pole region asked for by ``decay=`` or ``region=``.

    A decay ``σ`` is the half-plane ``Re s <= -σ`` in continuous time and
    the disk ``|z| <= exp(-σ dt)`` in discrete time.

    Examples
    --------
    >>> from controlext.synthesis.regions import region_for
    >>> region_for(decay=1.0), region_for(decay=1.0, dt=0.5)
    (HalfPlane(decay=1), Disk(radius=0.606531, center=0))
    """
    decay = check_decay(decay)
    if decay is not None and region is not None:
        raise ArgumentError("give either decay= or region=, not both")
    if region is not None and not isinstance(region, Region):
        raise ArgumentError(f"region must be a controlext Region; found "
                            f"{type(region).__name__}")
    if decay is not None:
        if dt:
            region = Disk(float(np.exp(-decay * sample_step(dt))),
                          domain='discrete')
        else:
            region = HalfPlane(decay)
    if region is not None:
        want = 'discrete' if dt else 'continuous'
        if region.domain not in ('any', want):
            raise RegionError(f"{region} is a {region.domain}-time region "
                              f"but the plant is {want}-time")
        if region.stable_interval(dt) is None:
            where = 'inside the unit circle' if dt else \
                'in the open left half-plane'
            raise RegionError(f"{region} has no point {where}: no stable "
                              "error dynamics lie in it (its parts do not "
                              "intersect there)")
    return region
