"""The convex stage's trade of γ for a moderate gain, against the
straightforward LMI.

Where the LMI optimum γ* is not attained (unstable modes), the gains
near it grow without bound: along the conditioned solutions
``γ − γ* ≈ c / ‖G‖``.  ``margin=`` chooses the point: the convex stage
solves at ``γ = margin · γ*`` for the best-conditioned Lyapunov matrix.
This script prints, for the plants of ``synthesis_scaling.py``, the
straightforward LMI (Theorem 3.10, one stage; measured in the same run)
and the convex stage (``refine=False``) at several margins: time ratio,
true γ against the baseline's and the spectral norm of the gain.

    python benchmarks/convex_margin.py [--family F] [n ...]

(default: family ``fast``, n = 30, the row where the default margin 1.02
is 2 % above the baseline's γ.)
"""

import argparse
import warnings

import numpy as np

import controlext as cx
from synthesis_scaling import SIGMA, plant, straightforward_lmi
from timing import best_of

MARGINS = (1.02, 1.005, 1.002, 1.0005, 1.0002, 1.0)


def main(sizes, family):
    print(f"family {family!r}, decay σ = {SIGMA:g}; γ = true H∞ norm")
    print(f"{'n':>3} {'design':>16} {'time s':>8} {'speed':>7} {'γ':>9} "
          f"{'γ/base':>8} {'‖G‖':>9}")
    for n in sizes:
        P = plant(n, family=family)
        tb, (lb, gb, nb, okb, status) = best_of(
            lambda: straightforward_lmi(P), repeat=1)
        print(f"{n:>3} {'straightforward':>16} {tb:>8.2f} {1.0:>7.1f} "
              f"{gb:>9.5f} {1.0:>8.5f} {nb:>9.3g}   "
              f"{status}{'' if okb else ', gain not stabilising'}",
              flush=True)
        for margin in MARGINS:
            tc, obs = best_of(lambda: cx.coupled_observer(
                P, decay=SIGMA, refine=False, margin=margin), repeat=1)
            print(f"{'':>3} {f'margin={margin:g}':>16} {tc:>8.2f} "
                  f"{tb / tc:>7.1f} {obs.hinf:>9.5f} {obs.hinf / gb:>8.5f} "
                  f"{np.linalg.norm(obs.G, 2):>9.3g}", flush=True)


if __name__ == '__main__':
    warnings.simplefilter('ignore', UserWarning)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('sizes', nargs='*', type=int, default=[30])
    parser.add_argument('--family', choices=['mixed', 'fast'],
                        default='fast')
    args = parser.parse_args()
    main(args.sizes, args.family)
