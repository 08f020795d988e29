"""What robust decay by default costs, and that it holds.

Every design is made twice in one run: with ``gain_tolerance=0`` (the
nominal optimum) and with the factories' defaults (its decay certified
under relative gain errors of 1e-6 and checked on the gain rounded to 6
significant digits).  The table gives both γ, the cost in γ, both times
and their ratio, and checks the default design independently of the
code that made it: the error matrix is rebuilt from the rounded gain and
from 200 gains with seeded random relative errors of 1e-6 in every
entry, and its slowest pole compared with the region's edge.

Plants: the paper's two (decay 2.5 and 1; one to three copies) and the
public plants of ``benchmarks/plants.py`` of 4-10 states (decay 0.5,
input disturbances and sensor noise 0.1, one and two copies).

    python benchmarks/robust_decay.py
    python benchmarks/robust_decay.py --group paper
"""

import argparse
import time
import warnings

import numpy as np

import controlext as cx
from plants import PAPER, PUBLIC, noise_model

#: relative gain errors of the random draws, and how many
EPS, DRAWS = 1e-6, 200


def cases(group):
    out = []
    if group in ('paper', 'all'):
        for name, (plant, decay) in PAPER.items():
            for N in (1, 2, 3):
                out.append((name, plant, decay, N, {}))
    if group in ('public', 'all'):
        for name, plant in PUBLIC.items():
            if not 4 <= plant.nstates <= 10:
                continue
            Bw, Dw = noise_model(plant)
            for N in (1, 2):
                out.append((name, plant, 0.5, N, dict(Bw=Bw, Dw=Dw)))
    return out


def design(plant, decay, N, noise, **options):
    if N == 1:
        return cx.hinf_observer(plant, decay=decay, **noise, **options)
    return cx.coupled_observer(plant, decay=decay, copies=N, **noise,
                               **options)


def slowest(obs, G):
    """The largest real part of the error poles of gain ``G``, rebuilt
    from the problem's matrices (not the observer's realisation)."""
    p = obs.problem
    Acl = p.Ae - G @ p.Ce
    return float(np.max(np.linalg.eigvals(Acl).real))


def holds(obs, decay, seed=0):
    """(6-digit rounding keeps the decay, every random draw keeps it)."""
    G = obs.G
    rounded = np.vectorize(lambda x: float(f"{x:.5e}"))(G)
    edge = -decay * (1 - 1e-9)
    rng = np.random.default_rng(seed)
    draws = all(slowest(obs, G * (1 + EPS * rng.uniform(-1, 1, G.shape)))
                <= edge for _ in range(DRAWS))
    return slowest(obs, rounded) <= edge, draws


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--group', choices=('paper', 'public', 'all'),
                        default='all')
    args = parser.parse_args(argv)
    warnings.simplefilter('ignore')
    head = (f"{'plant':<16}{'N':>2}  {'γ nominal':>11} {'γ default':>11} "
            f"{'cost':>8}  {'t nom':>6} {'t def':>6} {'ratio':>6}  "
            "rounded  draws")
    print(head)
    print('-' * len(head))
    costs, ratios = [], []
    for name, plant, decay, N, noise in cases(args.group):
        t0 = time.perf_counter()
        nominal = design(plant, decay, N, noise, gain_tolerance=0)
        t1 = time.perf_counter()
        default = design(plant, decay, N, noise)
        t2 = time.perf_counter()
        rounded, draws = holds(default, decay)
        cost = default.hinf / nominal.hinf - 1
        costs.append(cost)
        ratios.append((t2 - t1) / (t1 - t0))
        print(f"{name:<16}{N:>2}  {nominal.hinf:>11.7g} {default.hinf:>11.7g} "
              f"{cost:>+8.3%}  {t1 - t0:>6.2f} {t2 - t1:>6.2f} "
              f"{ratios[-1]:>6.2f}  {'kept' if rounded else 'LOST':<7}  "
              f"{'kept' if draws else 'LOST'}", flush=True)
    print(f"\n{len(costs)} designs: cost in γ median {np.median(costs):+.3%}, "
          f"largest {max(costs):+.3%}; time ratio median "
          f"{np.median(ratios):.2f}, largest {max(ratios):.2f}")


if __name__ == '__main__':
    main()
