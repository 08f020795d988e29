"""Public benchmark plants of 4-10 states (and the paper's two), with the
noise model the benchmarks use: a disturbance entering with the inputs
(``Bw = [B, 0]``) and sensor noise of size 0.1 on every measurement
(``Dw = [0, 0.1 I]``).  Sources:

* ``scalar``, ``second order`` — Li & Sanfelice, Section IV (their noise
  model: measurement noise only);
* ``747 lateral`` — Franklin, Powell & Emami-Naeini, *Feedback Control of
  Dynamic Systems* (the jet-transport yaw damper; MATLAB's "Yaw Damper for
  a 747 Jet Transport" example);
* ``AC1`` — COMPleib (Leibfritz), Hung & MacFarlane's aircraft;
* ``HE1`` — COMPleib, the helicopter of Keel, Bhattacharyya & Howze;
* ``batch reactor`` — Rosenbrock's unstable batch reactor (Green &
  Limebeer, *Linear Robust Control*);
* ``cart-pendulum`` — the linearised inverted pendulum on a cart
  (Franklin, Powell & Emami-Naeini; M = 1 kg, m = 0.1 kg, l = 0.5 m);
* ``dc motor`` — an armature-controlled DC motor with its angle measured
  (time constant 0.5 s).
"""

import numpy as np
import control as ct

PAPER = {
    'scalar': (ct.ss([[-0.5]], [[1.0]], [[1.0]], 0), 2.5),
    'second order': (ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]],
                           [[1.0, 2.0]], 0), 1.0),
}

PUBLIC = {
    '747 lateral': ct.ss([[-0.0558, -0.9968, 0.0802, 0.0415],
                          [0.5980, -0.1150, -0.0318, 0.0],
                          [-3.0500, 0.3880, -0.4650, 0.0],
                          [0.0, 0.0805, 1.0000, 0.0]],
                         [[0.0073, 0.0], [-0.4750, 0.0077], [0.1530, 0.1430],
                          [0.0, 0.0]],
                         [[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]], 0),
    'AC1': ct.ss([[0, 0, 1.132, 0, -1], [0, -0.0538, -0.1712, 0, 0.0705],
                  [0, 0, 0, 1, 0], [0, 0.0485, 0, -0.8556, -1.013],
                  [0, -0.2909, 0, 1.0532, -0.6859]],
                 [[0, 0, 0], [-0.12, 1, 0], [0, 0, 0], [4.419, 0, -1.665],
                  [1.575, 0, -0.0732]],
                 [[1, 0, 0, 0, 0], [0, 1, 0, 0, 0], [0, 0, 1, 0, 0]], 0),
    'HE1': ct.ss([[-0.0366, 0.0271, 0.0188, -0.4555],
                  [0.0482, -1.01, 0.0024, -4.0208],
                  [0.1002, 0.3681, -0.707, 1.42], [0, 0, 1, 0]],
                 [[0.4422, 0.1761], [3.5446, -7.5922], [-5.52, 4.49],
                  [0, 0]], [[0, 1, 0, 0]], 0),
    'batch reactor': ct.ss([[1.38, -0.2077, 6.715, -5.676],
                            [-0.5814, -4.29, 0, 0.675],
                            [1.067, 4.273, -6.654, 5.893],
                            [0.048, 4.273, 1.343, -2.104]],
                           [[0, 0], [5.679, 0], [1.136, -3.146],
                            [1.136, 0]],
                           [[1, 0, 1, -1], [0, 1, 0, 0]], 0),
    'cart-pendulum': ct.ss([[0, 1, 0, 0], [0, 0, -0.98, 0], [0, 0, 0, 1],
                            [0, 0, 21.56, 0]], [[0], [1], [0], [-2]],
                           [[1, 0, 0, 0], [0, 0, 1, 0]], 0),
    'dc motor': ct.ss([[0, 1], [0, -2.0]], [[0], [4.0]], [[1, 0]], 0),
}


def noise_model(plant):
    """``(Bw, Dw)``: input disturbances and sensor noise 0.1."""
    n, m = plant.B.shape
    p = plant.C.shape[0]
    Bw = np.hstack([plant.B, np.zeros((n, p))])
    Dw = np.hstack([np.zeros((p, m)), 0.1 * np.eye(p)])
    return Bw, Dw
