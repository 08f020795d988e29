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
  (time constant 0.5 s);
* ``quadruple tank`` — Johansson's quadruple-tank process at its
  minimum-phase operating point (K. H. Johansson, *IEEE Trans. Control
  Syst. Technol.* 8(3), 2000: tank areas 28/32 cm², outlets 0.071/0.057
  cm², levels 12.4/12.7/1.8/1.4 cm, γ₁ = 0.7, γ₂ = 0.6, k₁ = 3.33, k₂ =
  3.35, kc = 0.5), the two lower levels measured;
* ``two-mass spring`` — the ACC robust control benchmark (Wie &
  Bernstein, *J. Guidance* 15(5), 1992: m₁ = m₂ = k = 1), the force on
  the first mass, the position of the second measured (a rigid-body
  double integrator and an undamped mode at √2 rad/s);
* ``quarter car`` — the active suspension of MATLAB's "Robust Control of
  an Active Suspension" example (body 300 kg, wheel 60 kg, 16 kN/m and
  1 kN·s/m suspension, 190 kN/m tyre; road and actuator force in kN as
  inputs), body travel and suspension deflection measured;
* ``beam`` (:func:`beam`, not in ``PUBLIC``: 40 states) — the first 20
  bending modes of a pinned-pinned beam, 2 % damping, two displacement
  sensors, the modal displacements estimated (``examples/flexible_beam.py``);
* ``mass chain`` — four unit masses in a chain of unit springs and light
  dampers (0.02 N·s/m), the first tied to a wall, the force on the first mass, the positions of
  the first and the last measured: 8 states, four lightly damped modes.
* ``frame with mass driver`` — a three-storey shear frame with an active
  mass driver on its roof, after the structural-control benchmarks of
  Spencer, Dyke & Deoskar (*Earthquake Eng. Struct. Dyn.* 27(11), 1998):
  unit floor masses, storey stiffnesses 3/2/1 from the ground up, 2 %
  stiffness-proportional damping of the first mode, a driver of 5 % of a
  floor's mass tuned to that mode, pushed against the roof by an
  actuator of time constant 0.1 s; the three floor displacements, the
  driver's stroke and the actuator's force measured: 9 states, 5
  sensors, four lightly damped modes.
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


def _quadruple_tank():
    area = np.array([28.0, 32.0, 28.0, 32.0])
    outlet = np.array([0.071, 0.057, 0.071, 0.057])
    level = np.array([12.4, 12.7, 1.8, 1.4])
    g1, g2, k1, k2, kc = 0.7, 0.6, 3.33, 3.35, 0.5
    T = area / outlet * np.sqrt(2 * level / 981.0)
    A = np.diag(-1 / T)
    A[0, 2] = area[2] / (area[0] * T[2])
    A[1, 3] = area[3] / (area[1] * T[3])
    B = np.array([[g1 * k1 / area[0], 0], [0, g2 * k2 / area[1]],
                  [0, (1 - g2) * k2 / area[2]], [(1 - g1) * k1 / area[3], 0]])
    C = kc * np.eye(2, 4)
    return ct.ss(A, B, C, 0)


def _quarter_car():
    mb, mw, bs, ks, kt = 300.0, 60.0, 1000.0, 16000.0, 190000.0
    A = np.array([[0, 1, 0, 0],
                  [-ks / mb, -bs / mb, ks / mb, bs / mb],
                  [0, 0, 0, 1],
                  [ks / mw, bs / mw, -(ks + kt) / mw, -bs / mw]])
    B = np.array([[0, 0], [0, 1e3 / mb], [0, 0], [kt / mw, -1e3 / mw]])
    C = np.array([[1.0, 0, 0, 0], [1.0, 0, -1.0, 0]])
    return ct.ss(A, B, C, 0)


def _mass_chain(masses=4, spring=1.0, damper=0.02):
    K = 2 * np.eye(masses) - np.eye(masses, k=1) - np.eye(masses, k=-1)
    K[-1, -1] = 1.0                          # the last mass is free
    A = np.block([[np.zeros((masses, masses)), np.eye(masses)],
                  [-spring * K, -damper * K]])
    B = np.zeros((2 * masses, 1))
    B[masses, 0] = 1.0
    C = np.zeros((2, 2 * masses))
    C[0, 0] = C[1, masses - 1] = 1.0
    return ct.ss(A, B, C, 0)


def _frame_with_driver(stiffness=(3.0, 2.0, 1.0), driver=0.05, lag=0.1,
                       zeta=0.02):
    floors = len(stiffness)
    bodies = floors + 1                     # the floors and the driver
    K = np.zeros((bodies, bodies))
    for i, k in enumerate(stiffness):       # storey i joins floors i-1, i
        K[i, i] += k
        if i:
            K[i - 1, i - 1] += k
            K[i - 1, i] -= k
            K[i, i - 1] -= k
    first = np.sqrt(np.linalg.eigvalsh(K[:floors, :floors]).min())
    kd = driver * first**2                  # the driver tuned to mode 1
    roof, mass = floors - 1, floors
    K[np.ix_([roof, mass], [roof, mass])] += kd * np.array([[1, -1],
                                                            [-1, 1]])
    Minv = np.diag(1 / np.array([1.0] * floors + [driver]))
    damping = 2 * zeta / first * K
    force = np.zeros(bodies)
    force[mass], force[roof] = 1.0, -1.0   # between the roof and driver
    n = 2 * bodies + 1                      # and the actuator's force
    A = np.zeros((n, n))
    A[:bodies, bodies:2 * bodies] = np.eye(bodies)
    A[bodies:2 * bodies, :bodies] = -Minv @ K
    A[bodies:2 * bodies, bodies:2 * bodies] = -Minv @ damping
    A[bodies:2 * bodies, -1] = Minv @ force
    A[-1, -1] = -1 / lag
    B = np.zeros((n, 1))
    B[-1, 0] = 1 / lag
    C = np.zeros((5, n))
    C[:floors, :floors] = np.eye(floors)
    C[floors, mass], C[floors, roof] = 1.0, -1.0
    C[floors + 1, -1] = 1.0
    return ct.ss(A, B, C, 0)


PUBLIC.update({
    'quadruple tank': _quadruple_tank(),
    'two-mass spring': ct.ss([[0, 0, 1, 0], [0, 0, 0, 1], [-1, 1, 0, 0],
                              [1, -1, 0, 0]], [[0], [0], [1], [0]],
                             [[0, 1, 0, 0]], 0),
    'quarter car': _quarter_car(),
    'mass chain': _mass_chain(),
    'frame with mass driver': _frame_with_driver(),
})


def noise_model(plant):
    """``(Bw, Dw)``: input disturbances and sensor noise 0.1."""
    n, m = plant.B.shape
    p = plant.C.shape[0]
    Bw = np.hstack([plant.B, np.zeros((n, p))])
    Dw = np.hstack([np.zeros((p, m)), 0.1 * np.eye(p)])
    return Bw, Dw


def beam(modes=20, zeta=0.02):
    """``(plant, Cz)`` of ``examples/flexible_beam.py``: mode ``k`` at
    ``k²`` rad/s in the balanced modal form, sensors at 30 % and 70 % of
    the span, ``Cz`` picking the modal displacements."""
    A = np.zeros((2 * modes, 2 * modes))
    C = np.zeros((2, 2 * modes))
    for k in range(1, modes + 1):
        w, i = float(k**2), 2 * (k - 1)
        A[i:i + 2, i:i + 2] = [[0.0, w], [-w, -2 * zeta * w]]
        C[:, i] = np.sin(k * np.pi * 0.3), np.sin(k * np.pi * 0.7)
    Cz = np.zeros((modes, 2 * modes))
    Cz[np.arange(modes), 2 * np.arange(modes)] = 1.0
    return ct.ss(A, np.zeros((2 * modes, 1)), C, 0), Cz
