"""Pole regions for the estimation-error dynamics.

A region is an LMI region in the sense of Chilali and Gahinet: the set
``{z : L + M z + Mᵀ z̄ < 0}`` of the complex plane, given by its
*characteristic matrices* ``L = Lᵀ`` and ``M``.  The matrix ``Acl`` has all
its eigenvalues in the region if and only if there is ``X = Xᵀ > 0`` with

    L ⊗ X + M ⊗ Zᵀ + Mᵀ ⊗ Z < 0,   Z = X Acl,

which is linear in ``(X, Y)`` for ``Z = X Ae − Y Ce``; the engine in
:mod:`controlext.lmi` builds that constraint from :meth:`Region.blocks`.
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

import numpy as np

__all__ = ['Region', 'HalfPlane', 'Disk', 'Sector']

_TOL = 1e-9


class Region:
    """An intersection of LMI regions (base class).

    Subclasses define ``_parts``: a list of ``(L, M, margin, grad)`` with
    ``margin(λ) -> float`` (``<= 0`` inside) and ``grad(λ) -> (dg/dRe,
    dg/dIm)``.
    """

    #: 'continuous', 'discrete' or 'any': the time domain the region fits
    domain = 'any'

    def __init__(self, parts, label):
        self._parts = list(parts)
        self._label = label

    def __and__(self, other):
        if not isinstance(other, Region):
            return NotImplemented
        domains = {self.domain, other.domain} - {'any'}
        if len(domains) > 1:
            raise ValueError("cannot intersect a continuous-time region "
                             "with a discrete-time one")
        out = Region(self._parts + other._parts,
                     f"{self._label} & {other._label}")
        out.domain = domains.pop() if domains else 'any'
        return out

    def __repr__(self):
        return self._label

    __str__ = __repr__

    def blocks(self):
        """Characteristic matrices ``[(L, M), ...]`` of each part."""
        return [(np.atleast_2d(L), np.atleast_2d(M))
                for L, M, _, _ in self._parts]

    def margins(self, eigs):
        """Array ``(len(eigs), parts)`` of ``g(λ)``; ``<= 0`` inside."""
        eigs = np.atleast_1d(np.asarray(eigs, dtype=complex))
        return np.array([[g(lam) for _, _, g, _ in self._parts]
                         for lam in eigs]).reshape(len(eigs), -1)

    def margin_gradients(self, eigs):
        """Array ``(len(eigs), parts, 2)`` of ``(dg/dRe λ, dg/dIm λ)``."""
        eigs = np.atleast_1d(np.asarray(eigs, dtype=complex))
        return np.array([[dg(lam) for _, _, _, dg in self._parts]
                         for lam in eigs]).reshape(len(eigs), -1, 2)

    def worst_margin(self, eigs):
        """Largest margin over eigenvalues and parts (``<= 0`` inside)."""
        return float(np.max(self.margins(eigs)))

    def contains(self, eigs, tol=_TOL):
        """True if every eigenvalue lies in the region (to ``tol``)."""
        return self.worst_margin(eigs) <= tol


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

    def __init__(self, decay):
        decay = float(decay)
        if not np.isfinite(decay) or decay < 0:
            raise ValueError(f"decay must be a finite number >= 0; found "
                             f"{decay}")
        self.decay = decay
        super().__init__(
            [(2 * decay, 1.0, lambda z: z.real + decay,
              lambda z: (1.0, 0.0))],
            f"HalfPlane(decay={decay:g})")


class Disk(Region):
    """The disk ``|s - center| <= radius`` (continuous or discrete time).

    Examples
    --------
    >>> import controlext as cx
    >>> cx.Disk(0.9).contains([0.5 + 0.5j])
    True
    """

    def __init__(self, radius, center=0.0):
        radius, center = float(radius), float(center)
        if not np.isfinite(radius) or radius <= 0 or not np.isfinite(center):
            raise ValueError(f"radius must be a finite number > 0 and center "
                             f"finite; found radius={radius}, center={center}")
        self.radius, self.center = radius, center

        def grad(z):
            d = z - center
            r = abs(d)
            return (1.0, 0.0) if r == 0 else (d.real / r, d.imag / r)

        super().__init__(
            [(np.array([[-radius, -center], [-center, -radius]]),
              np.array([[0.0, 1.0], [0.0, 0.0]]),
              lambda z: abs(z - center) - radius, grad)],
            f"Disk(radius={radius:g}, center={center:g})")


class Sector(Region):
    """Damping ratio at least ``damping`` (continuous time): the cone
    ``|Im s| <= -Re s · tan(acos(damping))``.

    Examples
    --------
    >>> import controlext as cx
    >>> cx.Sector(0.5).contains([-1 + 1j])
    True
    """

    domain = 'continuous'

    def __init__(self, damping):
        damping = float(damping)
        if not 0 <= damping < 1:
            raise ValueError(f"damping must lie in [0, 1); found {damping}")
        self.damping = damping
        th = np.arccos(damping)
        s, c = np.sin(th), np.cos(th)
        super().__init__(
            [(np.zeros((2, 2)), np.array([[s, c], [-c, s]]),
              lambda z: s * z.real + c * abs(z.imag),
              lambda z: (s, c * np.sign(z.imag)))],
            f"Sector(damping={damping:g})")
