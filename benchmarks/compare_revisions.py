"""Time the same designs on this checkout and on another git revision.

Each revision runs in its own process (a temporary ``git worktree`` for
the baseline), the two alternating case by case so that both see the same
machine load; the table gives each design's time on both, their ratio
(this checkout / baseline) and both γ.  Only the public factories are
called, with arguments every revision accepts.

    python benchmarks/compare_revisions.py --baseline HEAD~1
    python benchmarks/compare_revisions.py --baseline HEAD~1 --cases paper
    python benchmarks/compare_revisions.py --baseline 65edc1d --cases public
    python benchmarks/compare_revisions.py --baseline 65edc1d --cases large

The ``public`` group designs ``hinf_observer`` and ``coupled_observer``
at decay 0.5 on every public plant of 4-10 states of
``benchmarks/plants.py`` (input disturbances and sensor noise 0.1) and
prints, for each factory, the median and the largest time on both
revisions (the speed targets: medians of 0.5 s for ``hinf_observer`` and
1 s for ``coupled_observer``, none above 3 s).  The ``large`` group
designs the 40-state beam of ``examples/flexible_beam.py`` (Luenberger
and pair, decay 0.5; targets 5 s and 10 s) and a 60-state pair of each
plant family of ``benchmarks/synthesis_scaling.py`` (decay 1; target 20
s).
"""

import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent

#: name -> Python source of a zero-argument expression returning an observer
CASES = {
    'paper': {
        'scalar N=1': "cx.hinf_observer(scalar, decay=2.5)",
        'scalar N=2': "cx.coupled_observer(scalar, decay=2.5)",
        'scalar N=3': "cx.coupled_observer(scalar, decay=2.5, copies=3)",
        '2nd order N=1': "cx.hinf_observer(second, decay=1.0)",
        '2nd order N=2': "cx.coupled_observer(second, decay=1.0)",
        '2nd order N=3': "cx.coupled_observer(second, decay=1.0, copies=3)",
    },
    'gi': {
        'GI decay 1': "cx.gi_observer(gi_plant, gi_bw, decay=1.0)",
        'GI augmented': "cx.gi_observer(gi_plant, gi_bw, decay=1.0, "
                        "augmented=True)",
        'GI pair': "cx.gi_observer(gi_plant, gi_bw, decay=1.0, copies=2)",
    },
}

CASES['large'] = {
    'beam hinf': "cx.hinf_observer(beam()[0], decay=0.5, Cz=beam()[1])",
    'beam pair': "cx.coupled_observer(beam()[0], decay=0.5, Cz=beam()[1])",
    'n=60 mixed pair': "cx.coupled_observer(scaling(60), decay=1.0)",
    'n=60 fast pair': "cx.coupled_observer(scaling(60, family='fast'), "
                      "decay=1.0)",
}

sys.path.insert(0, str(ROOT / 'benchmarks'))
from plants import PUBLIC  # noqa: E402

CASES['public'] = {
    f'{name} {label}': f"cx.{factory}(PUBLIC[{name!r}], decay=0.5, "
                       f"**noise(PUBLIC[{name!r}]))"
    for name, plant in PUBLIC.items() if 4 <= plant.nstates <= 10
    for label, factory in (('hinf', 'hinf_observer'),
                           ('pair', 'coupled_observer'))}

RUNNER = r'''
import json, sys, time, warnings
import numpy as np
import control as ct
import controlext as cx
sys.path.insert(0, sys.argv[2])
from plants import PUBLIC, beam
from synthesis_scaling import plant as scaling
def noise(plant):
    from plants import noise_model
    Bw, Dw = noise_model(plant)
    return dict(Bw=Bw, Dw=Dw)
warnings.simplefilter('ignore')
scalar = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
second = ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]], 0)
gi_plant = ct.ss([[-1.0, 1.0], [0.0, -2.0]], [[0.0], [1.0]],
                 [[1.0, 0.0], [1.0, 0.0]], 0)
gi_bw = [[0.5, 0.2], [0.0, 1.0]]
expr = sys.argv[1]
start = time.perf_counter()
obs = eval(expr)
elapsed = time.perf_counter() - start
print(json.dumps(dict(time=elapsed, gamma=float(obs.hinf))))
'''


def run(tree, expr):
    env = dict(os.environ, PYTHONPATH=str(tree))
    out = subprocess.run([sys.executable, '-c', RUNNER, expr,
                          str(ROOT / 'benchmarks')], env=env,
                         capture_output=True, text=True, check=True,
                         cwd=tempfile.gettempdir())
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--baseline', default='HEAD~1')
    parser.add_argument('--cases', nargs='*', default=list(CASES))
    parser.add_argument('--repeat', type=int, default=1)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        base = pathlib.Path(tmp) / 'baseline'
        subprocess.run(['git', '-C', str(ROOT), 'worktree', 'add', '-q',
                        '--detach', str(base), args.baseline], check=True)
        try:
            print(f"{'case':<22}{'this s':>9}{'base s':>9}{'ratio':>8}"
                  f"{'γ this':>11}{'γ base':>11}")
            times = {}
            for group in args.cases:
                for name, expr in CASES[group].items():
                    mine, theirs = [], []
                    for _ in range(args.repeat):
                        mine.append(run(ROOT, expr))
                        theirs.append(run(base, expr))
                    t1 = min(r['time'] for r in mine)
                    t0 = min(r['time'] for r in theirs)
                    if group == 'public':
                        # the targets are over the public plants only
                        times.setdefault(name.split()[-1], []).append(
                            (t1, t0))
                    print(f"{name:<22}{t1:>9.3f}{t0:>9.3f}{t1 / t0:>8.2f}"
                          f"{mine[0]['gamma']:>11.5f}"
                          f"{theirs[0]['gamma']:>11.5f}", flush=True)
            if 'public' in args.cases:
                print()
                for label in ('hinf', 'pair'):
                    pairs = np.array(times[label])
                    med, big = np.median(pairs, axis=0), pairs.max(axis=0)
                    print(f"{label + ' median':<22}{med[0]:>9.3f}{med[1]:>9.3f}"
                          f"{med[0] / med[1]:>8.2f}   largest {big[0]:.3f}"
                          f" / {big[1]:.3f} s")
        finally:
            subprocess.run(['git', '-C', str(ROOT), 'worktree', 'remove',
                            '--force', str(base)], check=True)


if __name__ == '__main__':
    main()
