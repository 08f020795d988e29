"""Design maps against a Python loop of control.linfnorm (same run).

1. The paper's scalar coupled pair (k1 = k2 = 2) over a 200 × 200 grid of
   (ℓ1, ℓ2): the closed form against the loop.
2. A 4-state error system (the second-order coupled pair of Section IV-B)
   over a 40 × 40 grid: the batched evaluation against the loop.
3. An 8-state MIMO error system (a coupled pair on the Boeing 747 lateral
   model of examples/boeing747_lateral.py) over a 30 × 30 grid.

Each time is the best of three runs.

    python benchmarks/design_maps.py
"""

import numpy as np
import control as ct

import controlext as cx
from controlext.paper.tables import MU_SECOND_ORDER, scalar_plant, \
    second_order_plant
from timing import best_of


def loop(obs, xe, xs, ye, ys):
    out = np.full((len(ys), len(xs)), np.inf)
    for i, yv in enumerate(ys):
        for j, xv in enumerate(xs):
            G = obs.G.copy()
            G[xe], G[ye] = xv, yv
            sys = ct.ss(*obs.problem.error_system(G))
            if np.max(np.linalg.eigvals(sys.A).real) < 0:
                out[i, j] = ct.linfnorm(sys)[0]
    return out


def compare(name, obs, xe, xs, ye, ys):
    t_loop, ref = best_of(lambda: loop(obs, xe, xs, ye, ys))
    t_map, m = best_of(lambda: cx.design_map(obs, xe, xs, ye, ys))
    fin = np.isfinite(ref)
    err = np.max(np.abs(m.gamma[fin] - ref[fin]) / ref[fin])
    same = np.array_equal(np.isfinite(m.gamma), fin)
    print(f"{name:<34} {ref.size:>7} {t_loop:>9.3f} {t_map:>9.4f} "
          f"{t_loop / t_map:>8.1f} {err:>10.2e} {str(same):>6}")


def main():
    print(f"{'map':<34} {'points':>7} {'loop s':>9} {'map s':>9} "
          f"{'ratio':>8} {'max rel':>10} {'stab=':>6}")
    pair = cx.CoupledObserver.from_pair(scalar_plant(), 2.0, 2.0, 0.0, 0.0)
    ell = np.linspace(-6, 6, 200)
    compare('scalar pair, 200 x 200 (closed)', pair, (0, 1), ell, (1, 0),
            ell)
    obs = cx.CoupledObserver(second_order_plant(), MU_SECOND_ORDER)
    compare('2nd-order pair, 40 x 40 (batched)', obs, (1, 1),
            np.linspace(-1, 1, 40), (2, 0), np.linspace(-1.5, 0.5, 40))
    A = [[-0.0558, -0.9968, 0.0802, 0.0415], [0.5980, -0.1150, -0.0318, 0],
         [-3.0500, 0.3880, -0.4650, 0], [0, 0.0805, 1.0000, 0]]
    B = [[0.0073, 0], [-0.4750, 0.0077], [0.1530, 0.1430], [0, 0]]
    C = [[0, 1, 0, 0], [0, 0, 0, 1]]
    plant = ct.ss(A, B, C, np.zeros((2, 2)))
    L = cx.luenberger_observer(plant, [-1, -1.5, -2, -2.5]).L
    jet = cx.CoupledObserver(plant, np.kron(np.eye(2), L))
    compare('747 pair, 8 states, 30 x 30', jet, (0, 2),
            L[0, 0] + np.linspace(-1, 1, 30), (4, 1),
            np.linspace(-1, 1, 30))


if __name__ == '__main__':
    main()
