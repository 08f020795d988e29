"""The trade-off of N = 1, 2, 3 coupled observers and the Kalman filter
on the paper's plants and public benchmark plants (benchmarks/plants.py):
γ, the floor γ∞*, the H2 norm, the gain norm, the transient, the decay
and its loss under relative gain errors of 1e-3, and the design time;
then the designs minimising the H2 norm in the same region (N = 1, 2) and
the mixed one-copy design whose γ may be 10 % above the H∞ design's.

    python benchmarks/tradeoff_table.py
    python benchmarks/tradeoff_table.py --decay 1.0 --plants AC1 HE1
"""

import argparse
import pathlib
import sys
import time
import warnings

import controlext as cx

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from plants import PAPER, PUBLIC, noise_model  # noqa: E402


def table(name, plant, decay, noise):
    rows, times = [], {}
    for N in (1, 2, 3):
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter('ignore', cx.GainWarning)
            obs = cx.hinf_observer(plant, decay=decay, name='N = 1', **noise) \
                if N == 1 else cx.coupled_observer(
                    plant, decay=decay, copies=N, name=f'N = {N}', **noise)
        times[obs.name] = time.perf_counter() - t0
        rows.append(obs)
    gamma1 = rows[0].hinf
    mixed = [('H2, N = 1', 1, {}), ('H2, N = 2', 2, {}),
             ('mixed N = 1', 1, dict(max_hinf=1.1 * gamma1))]
    for label, N, extra in mixed if gamma1 > 0 else []:
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter('ignore', cx.GainWarning)
            kw = dict(noise, decay=decay, name=label, objective='h2',
                      **extra)
            obs = cx.hinf_observer(plant, **kw) if N == 1 else \
                cx.coupled_observer(plant, copies=N, **kw)
        times[label] = time.perf_counter() - t0
        rows.append(obs)
    comparison = cx.compare(*rows)
    print(f"\n{name} (decay {decay:g}; design times "
          + ', '.join(f"{k}: {v:.2f} s" for k, v in times.items()) + ")")
    print(comparison)
    heads = [o.name for o in rows[1:] if 'headroom' in o.report.stats]
    if heads:
        print(f"  headroom: {', '.join(heads)} returned the one-copy "
              "design (it is at the floor)")
    return times


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--decay', type=float, default=0.5,
                        help='decay of the public plants (default 0.5)')
    parser.add_argument('--plants', nargs='*', default=None)
    args = parser.parse_args()
    wanted = set(args.plants) if args.plants else None
    all_times = []
    for name, (plant, decay) in PAPER.items():
        if wanted is None or name in wanted:
            all_times += table(name, plant, decay, {}).values()
    for name, plant in PUBLIC.items():
        if wanted is None or name in wanted:
            Bw, Dw = noise_model(plant)
            all_times += table(name, plant, args.decay,
                               dict(Bw=Bw, Dw=Dw)).values()
    print(f"\ntotal design time {sum(all_times):.1f} s")


if __name__ == '__main__':
    main()
