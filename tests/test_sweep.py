"""Trade-off curves: each point checked against a closed form or a
monotonicity the optimum must have; the Pareto front against a brute-force
domination test."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import control as ct

import controlext as cx
from controlext.synthesis.tradeoff import Tradeoff

UNSTABLE = ct.ss([[1.0]], [[1.0]], [[1.0]], 0)
SECOND = ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]], 0)


def test_max_gain_curve_closed_form():
    """γ = κ / (κ − 1) for the unstable scalar plant at decay 2."""
    kappas = [4.0, 10.0, 30.0, 100.0]          # decay 2 needs L >= 3
    s = cx.sweep(UNSTABLE, 'max_gain', kappas, decay=2.0)
    assert s.metric('hinf') == pytest.approx(
        [k / (k - 1) for k in kappas], rel=1e-6)
    assert s.metric('gain_norm') == pytest.approx(kappas, rel=1e-6)


def test_decay_curve_is_monotone_and_holds_each_decay():
    decays = [0.5, 1.0, 1.5, 2.0]
    s = cx.sweep(SECOND, 'decay', decays)
    gammas = s.metric('hinf')
    assert np.all(np.diff(gammas) >= -1e-6 * gammas[1:])
    assert np.all(s.metric('decay') >= np.array(decays) - 1e-6)


def test_copies_never_worse_than_one_and_parallel_is_the_same():
    s = cx.sweep(ct.ss([[-0.5]], [[1.0]], [[1.0]], 0), 'copies', [1, 2, 3],
                 decay=2.5, gain_tolerance=0)
    g = s.metric('hinf')
    assert g[1] <= g[0] and g[2] <= g[0]
    assert g == pytest.approx([0.8, 0.4953, 0.3196], abs=1e-4)   # paper
    with ThreadPoolExecutor(2) as pool:
        again = cx.sweep(ct.ss([[-0.5]], [[1.0]], [[1.0]], 0), 'copies',
                         [1, 2, 3], decay=2.5, gain_tolerance=0,
                         executor=pool)
    assert again.metric('hinf') == pytest.approx(g, rel=1e-12)


def test_front_against_brute_force():
    rng = np.random.default_rng(0)
    rows = [Tradeoff(name=str(k), hinf=float(a), floor=None, luenberger=None,
                     gain_norm=1.0, h2=1.0, peak=1.0, settling_time=float(b),
                     decay=1.0) for k, (a, b) in
            enumerate(rng.uniform(size=(40, 2)))]
    s = cx.Sweep('decay', list(range(40)), rows)
    front = s.front('settling_time', 'hinf')
    pts = [(r.settling_time, r.hinf) for r in rows]
    brute = {k for k, (x, y) in enumerate(pts)
             if not any(u <= x and v <= y and (u, v) != (x, y)
                        for u, v in pts)}
    assert set(front) == brute
    assert [pts[k][0] for k in front] == sorted(pts[k][0] for k in front)


def test_bad_sweeps_are_refused():
    with pytest.raises(cx.ParameterError, match='parameter'):
        cx.sweep(SECOND, 'margin', [1.0])
    with pytest.raises(cx.ArgumentError, match='swept parameter'):
        cx.sweep(SECOND, 'decay', [1.0], decay=2.0)
    with pytest.raises(cx.ArgumentError, match='at least one value'):
        cx.sweep(SECOND, 'decay', [])


def test_sweep_plot_front(tmp_path):
    pytest.importorskip('matplotlib')
    import matplotlib
    matplotlib.use('Agg')
    s = cx.sweep(ct.ss([[-0.5]], [[1.0]], [[1.0]], 0), 'copies', [1, 2, 3],
                 decay=2.5, gain_tolerance=0)
    cp = cx.sweep_plot(s, y='hinf', x='settling_time')
    cp.figure.savefig(tmp_path / 'front.png')
    assert (tmp_path / 'front.png').stat().st_size > 5000
