"""The two plants of Li & Sanfelice, Section IV.

Examples
--------
>>> from controlext.paper.plants import scalar_plant, second_order_plant
>>> scalar_plant().A.tolist(), second_order_plant().C.tolist()
([[-0.5]], [[1.0, 2.0]])
"""

import control as ct

__all__ = ['scalar_plant', 'second_order_plant']


def scalar_plant(a=-0.5):
    """The scalar plant (4): ``x' = a x``, ``y = x + m``, ``a = -0.5``.

    Parameters
    ----------
    a : float, optional
        The plant's pole.

    Returns
    -------
    control.StateSpace
    """
    return ct.ss([[a]], [[1.0]], [[1.0]], [[0.0]], name='scalar')


def second_order_plant():
    """The second-order plant of Section IV-B.

    Returns
    -------
    control.StateSpace
    """
    return ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]],
                 [[0.0]], name='second_order')
