"""One observer for a DC motor whose load inertia is not known.

The motor (J = 0.01 kg m², b = 0.1 N m s, K = 0.01 N m/A, R = 1 Ω,
L = 0.5 H; states angle, speed, current; the angle measured) drives a
load that takes its inertia from 0.005 to 0.04 kg m².  The observer must
converge at rate 3 whatever the load.  A design for the nominal inertia
loses that rate on the lightest and the heaviest load; a design for the
three models J = 0.01, 0.005, 0.04 keeps it on every load in between, at
a higher γ.  Run:  python examples/motor_load_inertia.py
"""

import numpy as np
import matplotlib.pyplot as plt
import control as ct

import controlext as cx

DECAY = 3.0


def motor(J, b=0.1, K=0.01, R=1.0, L=0.5):
    A = [[0.0, 1.0, 0.0], [0.0, -b / J, K / J], [0.0, -K / L, -R / L]]
    return ct.ss(A, [[0.0], [0.0], [1 / L]], [[1.0, 0.0, 0.0]], 0,
                 name='motor', states=['theta', 'omega', 'i'],
                 inputs=['V'], outputs=['theta'])


models = cx.model_set(motor, [0.01, 0.005, 0.04])      # nominal first
nominal = cx.hinf_observer(models[0], decay=DECAY, name='nominal')
robust = cx.hinf_observer(models, decay=DECAY, name='three models')
print(robust.report)
print()

inertia = np.linspace(0.005, 0.04, 36)
checks = {obs.name: cx.check_models(obs, motor, inertia)
          for obs in (nominal, robust)}
for name, check in checks.items():
    print(f"{name:>13}: worst decay {check.worst_decay:.4g}, worst γ "
          f"{check.worst_hinf:.4g} over J in [0.005, 0.04]; region kept "
          f"on {int(np.sum(check.in_region))} of {inertia.size} loads")
print()
print(cx.compare(nominal, robust, kalman=False))

fig, (left, gamma, rate) = plt.subplots(1, 3, figsize=(15, 4.4))
colours = {'nominal': 'C0', 'three models': 'C3'}
for obs in (nominal, robust):
    for J, marker, model in zip((0.01, 0.005, 0.04), 'osd',
                                (obs.on(P) for P in models)):
        poles = ct.poles(model)
        left.plot(poles.real, poles.imag, marker, color=colours[obs.name],
                  mfc='none', ms=8, label=f"{obs.name}, J = {J:g}")
left.axvspan(-12, -DECAY, color='0.92', zorder=0)
left.axvline(-DECAY, color='k', lw=1, ls='--')
left.set_xlim(-12, 0.5)
left.set_xlabel('Re s')
left.set_ylabel('Im s')
left.set_title(f'error poles on each model (region Re s ≤ −{DECAY:g})')
left.legend(fontsize=8, ncol=2, loc='upper left')
for name, check in checks.items():
    gamma.plot(check.values, check.hinf, color=colours[name], label=name)
    rate.plot(check.values, check.decay, color=colours[name], label=name)
rate.axhline(DECAY, color='k', lw=1, ls='--', label='decay asked')
gamma.set_ylabel('γ (H∞, noise → error)')
rate.set_ylabel('decay rate')
for ax, what in ((gamma, 'γ'), (rate, 'decay')):
    for J in (0.01, 0.005, 0.04):
        ax.axvline(J, color='0.75', lw=0.8)
    ax.set_xlabel('load inertia J (kg m²)')
    ax.set_title(f'{what} over the load (grey: the design models)')
    ax.legend(fontsize=8)
for ax in (left, gamma, rate):
    ax.grid(True, alpha=0.3)
fig.tight_layout()
plt.savefig('motor_load_inertia.png', dpi=100)
