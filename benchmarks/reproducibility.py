"""Does a design move with the last bits of its data or with the BLAS?

Each design is made on the plant as given, on the plant with every entry
of A and C moved by a relative 1e-13 (random signs, three draws) and with
BLAS on one and on two threads; the table gives γ of each and the largest
relative spread (the target: 0.2 %).  The designs are the factories'
defaults (robust decay); ``--nominal`` makes them with
``gain_tolerance=0``.

    python benchmarks/reproducibility.py [--draws 3] [--nominal]
    python benchmarks/reproducibility.py --cases scalar:2 HE1:2
"""

import argparse
import warnings

import control as ct
import numpy as np
from threadpoolctl import threadpool_limits

import controlext as cx
from plants import PAPER, PUBLIC, noise_model

CASES = [('scalar', 2), ('scalar', 3), ('second order', 1),
         ('second order', 2), ('second order', 3), ('747 lateral', 1),
         ('747 lateral', 2), ('HE1', 1), ('HE1', 2), ('mass chain', 2)]


def design(name, copies, plant, **options):
    if name in PAPER:
        decay, kw = PAPER[name][1], dict(options)
    else:
        Bw, Dw = noise_model(plant)
        decay, kw = 0.5, dict(Bw=Bw, Dw=Dw, **options)
    if copies == 1:
        return cx.hinf_observer(plant, decay=decay, **kw).hinf
    return cx.coupled_observer(plant, decay=decay, copies=copies, **kw).hinf


def perturbed(plant, rng, size=1e-13):
    A, B, C, D = (np.asarray(M, dtype=float) for M in (plant.A, plant.B,
                                                       plant.C, plant.D))
    A = A * (1 + size * rng.choice([-1.0, 1.0], A.shape))
    C = C * (1 + size * rng.choice([-1.0, 1.0], C.shape))
    return ct.ss(A, B, C, D, plant.dt)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--draws', type=int, default=3)
    parser.add_argument('--nominal', action='store_true',
                        help='gain_tolerance=0 (the nominal optima)')
    parser.add_argument('--cases', nargs='*', default=None,
                        help='NAME:COPIES of the cases to run (default all)')
    args = parser.parse_args()
    cases = CASES if args.cases is None else [
        (item.rsplit(':', 1)[0], int(item.rsplit(':', 1)[1]))
        for item in args.cases]
    options = dict(gain_tolerance=0) if args.nominal else {}
    warnings.simplefilter('ignore', cx.GainWarning)
    print(f"{'plant':<14} {'N':>2} {'γ as given':>12} {'1 thread':>12} "
          f"{'2 threads':>12} {'perturbed (min..max)':>26} {'spread':>8}")
    for name, copies in cases:
        plant = PAPER[name][0] if name in PAPER else PUBLIC[name]
        rng = np.random.default_rng(0)
        base = design(name, copies, plant, **options)
        threads = []
        for count in (1, 2):
            with threadpool_limits(limits=count, user_api='blas'):
                threads.append(design(name, copies, plant, **options))
        moved = [design(name, copies, perturbed(plant, rng), **options)
                 for _ in range(args.draws)]
        values = [base] + threads + moved
        spread = max(values) / min(values) - 1
        print(f"{name:<14} {copies:>2} {base:>12.7g} {threads[0]:>12.7g} "
              f"{threads[1]:>12.7g} {min(moved):>12.7g}..{max(moved):<12.7g} "
              f"{spread:>8.2%}", flush=True)


if __name__ == '__main__':
    main()
