"""A realistic MIMO plant: Boeing 747 lateral dynamics at cruise.

States: sideslip angle beta, yaw rate r, roll rate p, bank angle phi;
inputs: rudder and aileron; measured: yaw rate and bank angle.  Model
from Franklin, Powell & Emami-Naeini, *Feedback Control of Dynamic
Systems* (the jet-transport yaw damper), also used by MATLAB's "Yaw
Damper for a 747 Jet Transport" example.  Luenberger, coupled pair and
three coupled observers for a decay rate of 0.5 (the Dutch-roll mode
decays at only 0.03).  Run:  python examples/boeing747_lateral.py
"""

import numpy as np
import matplotlib.pyplot as plt
from control.matlab import ss, pole

import controlext as cx
from controlext.matlab import hinfobs, coupledobs, hinfnorm

A = [[-0.0558, -0.9968, 0.0802, 0.0415],
     [0.5980, -0.1150, -0.0318, 0.0],
     [-3.0500, 0.3880, -0.4650, 0.0],
     [0.0, 0.0805, 1.0000, 0.0]]
B = [[0.0073, 0.0], [-0.4750, 0.0077], [0.1530, 0.1430], [0.0, 0.0]]
C = [[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
sys = ss(A, B, C, np.zeros((2, 2)))
print("open-loop poles:", np.round(pole(sys), 4))

designs = {'Luenberger': hinfobs(sys, 0.5),
           'coupled, N = 2': coupledobs(sys, 0.5),
           'coupled, N = 3': coupledobs(sys, 0.5, 3)}
for name, obs in designs.items():
    print(f"{name:<16} gamma = {hinfnorm(obs)[0]:.4f}  decay = "
          f"{obs.decay:.3f}  |gain| = {np.linalg.norm(obs.G, 2):.2f}")

# (a) transient from a wrong initial estimate, no noise: the H∞ norm
#     says nothing about this, and the coupled designs converge later
# (b) sensor noise that is worst for the Luenberger design: a sinusoid at
#     its peak frequency in its worst input direction (x0 = 0)
fig, ax = plt.subplots(1, 2, figsize=(12, 4.4))
t = np.linspace(0, 15, 1501)
resp = cx.simulate(sys, list(designs.values()), t,
                   initial_state=[0.1, 0.0, 0.0, 0.05])
cx.error_plot(resp, labels=list(designs), ax=np.array([[ax[0]]]),
              title='(a) initial estimation error, no noise')
ninf, wpk = hinfnorm(designs['Luenberger'])
T = designs['Luenberger'](1j * wpk)
v = np.linalg.svd(T)[2][0].conj()
t = np.linspace(0, 60, 6001)
w = 0.05 * np.real(np.outer(v, np.exp(1j * wpk * t)))
resp = cx.simulate(sys, list(designs.values()), t, noise=w)
cx.error_plot(resp, labels=list(designs), ax=np.array([[ax[1]]]),
              title=f'(b) worst-case noise for Luenberger ({wpk:.2f} rad/s)')
for k, name in enumerate(designs):
    e = resp.outputs[[resp.output_labels.index(f'e{k + 1}[{i}]')
                      for i in range(4)]]
    print(f"{name:<16} error amplitude under that noise: "
          f"{np.max(np.linalg.norm(e[:, -2000:], axis=0)):.4f}")
fig.suptitle('Boeing 747 lateral dynamics: estimation error')
fig.tight_layout()
plt.savefig('boeing747_lateral.png', dpi=100)
