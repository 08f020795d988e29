"""MATLAB-style names for controlext.

Import alongside ``control.matlab``; nothing here changes a global
setting::

    from control.matlab import *
    from controlext.matlab import *

Examples
--------
>>> from control.matlab import ss
>>> from controlext.matlab import hinfnorm, hinfobs
>>> sys = ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]], 0)
>>> obs = hinfobs(sys, 1.0)
>>> ninf, fpeak = hinfnorm(obs)
>>> bool(ninf < 0.2852)
True
"""

from .norms import hinfnorm
from .luenberger import luenberger_observer, hinf_observer
from .coupled import coupled_observer
from .gi import gi_observer
from .simulate import simulate

__all__ = ['hinfnorm', 'luenobs', 'hinfobs', 'coupledobs', 'giobs',
           'obsim']

#: ``L = luenobs(sys, p)``: Luenberger observer with poles ``p``
luenobs = luenberger_observer
#: ``obs = hinfobs(sys, decay)``: H∞-optimal observer
hinfobs = hinf_observer
#: ``obs = coupledobs(sys, decay, copies)``: coupled observers
coupledobs = coupled_observer
#: ``obs = giobs(sys, Bw, decay)``: GI observer
giobs = gi_observer
#: ``resp = obsim(sys, observers, t, ...)``: simulate plant and observers
obsim = simulate
