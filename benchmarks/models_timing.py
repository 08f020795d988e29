"""Time of a design for three plant models against one, in one run.

Each public plant of 4 to 8 states gives three models: the plant, and the
plant 20 % slower and 20 % faster (``A`` scaled by 0.8 and 1.2).  Every
design uses the default options, decay 0.5 and the noise model of
``plants.noise_model``; ``hinf_observer`` and ``coupled_observer`` are
timed on the nominal plant alone and on the three models, best of
``--repeat`` runs, in the same process.

    python benchmarks/models_timing.py [--repeat 2] [--kinds hinf,coupled]
"""

import argparse
import statistics
import warnings

import control as ct
import numpy as np

import controlext as cx
from plants import PUBLIC, noise_model
from timing import best_of

SCALES = (1.0, 0.8, 1.2)
DECAY = 0.5
FACTORIES = {'hinf': cx.hinf_observer, 'coupled': cx.coupled_observer}


def models_of(plant):
    A, B, C, D = (np.asarray(M) for M in (plant.A, plant.B, plant.C,
                                          plant.D))
    return [ct.ss(s * A, B, C, D) for s in SCALES]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--repeat', type=int, default=2)
    parser.add_argument('--kinds', default='hinf,coupled')
    args = parser.parse_args()
    rows, totals = [], [0.0, 0.0]
    print(f"{'plant':<16} {'kind':<8} {'one model s':>11} "
          f"{'three s':>9} {'ratio':>6} {'γ one':>9} {'γ three':>9} "
          f"{'decay on all (one)':>19}")
    for name, plant in PUBLIC.items():
        if not 4 <= plant.nstates <= 8:
            continue
        Bw, Dw = noise_model(plant)
        models = models_of(plant)
        for kind in args.kinds.split(','):
            factory = FACTORIES[kind]
            with warnings.catch_warnings():
                warnings.simplefilter('ignore', cx.GainWarning)
                try:
                    t1, one = best_of(lambda: factory(
                        models[0], decay=DECAY, Bw=Bw, Dw=Dw), args.repeat)
                    t3, three = best_of(lambda: factory(
                        models, decay=DECAY, Bw=Bw, Dw=Dw), args.repeat)
                except cx.ControlextError as exc:
                    print(f"{name:<16} {kind:<8} refused: {exc}"[:100])
                    continue
            lost = min(one.on(P).decay for P in models)
            rows.append(t3 / t1)
            totals[0] += t1
            totals[1] += t3
            print(f"{name:<16} {kind:<8} {t1:>11.3f} {t3:>9.3f} "
                  f"{t3 / t1:>6.2f} {one.hinf:>9.4g} {three.hinf:>9.4g} "
                  f"{lost:>19.4g}")
    print(f"\nthree models against one: median ratio "
          f"{statistics.median(rows):.2f}, largest {max(rows):.2f} "
          f"over {len(rows)} designs; all designs together "
          f"{totals[1]:.1f} s against {totals[0]:.1f} s "
          f"({totals[1] / totals[0]:.2f}x)")


if __name__ == '__main__':
    main()
