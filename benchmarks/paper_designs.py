"""Time the paper's designs against a same-run baseline.

Baseline: the convex stage alone (``refine=False``, the straightforward
LMI of Theorems 3.10/3.12).  For each design the table gives the time of
the default (refined) design, its ratio to the baseline, and both γ; then
the same refined design with its starts on a 2-process pool
(``executor=``), which must give the same γ.

    python benchmarks/paper_designs.py
"""

from concurrent.futures import ProcessPoolExecutor

import controlext as cx
from controlext.paper import scalar_plant, second_order_plant
from timing import best_of


def main():
    cases = [('scalar', scalar_plant(), 2.5), ('2nd order',
                                               second_order_plant(), 1.0)]
    print(f"{'case':<12}{'N':>3}{'LMI s':>9}{'refined s':>11}{'ratio':>8}"
          f"{'γ LMI':>10}{'γ refined':>11}{'2 procs s':>11}{'γ':>9}")
    with ProcessPoolExecutor(2) as pool:
        cx.hinf_observer(cases[0][1], decay=2.5,
                         executor=pool)              # start the workers
        for name, plant, sigma in cases:
            for N in (1, 2, 3):
                if N == 1:
                    make = lambda refine, pool=None: cx.hinf_observer(
                        plant, decay=sigma, refine=refine, executor=pool)
                else:
                    make = lambda refine, pool=None: cx.coupled_observer(
                        plant, decay=sigma, copies=N, refine=refine,
                        executor=pool)
                t_lmi, lmi = best_of(lambda: make(False))
                t_ref, ref = best_of(lambda: make(True), repeat=1)
                t_par, par = best_of(lambda: make(True, pool), repeat=1)
                print(f"{name:<12}{N:>3}{t_lmi:>9.3f}{t_ref:>11.3f}"
                      f"{t_ref / t_lmi:>8.1f}{lmi.hinf:>10.4f}"
                      f"{ref.hinf:>11.4f}{t_par:>11.3f}{par.hinf:>9.4f}",
                      flush=True)


if __name__ == '__main__':
    main()
