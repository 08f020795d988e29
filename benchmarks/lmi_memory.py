"""Peak memory of the observer LMI against the estimate the engine
refuses by (controlext.synthesis.lmi.lmi_memory).

Each size runs in its own process (its peak resident size is its own);
prints the measured increase over the interpreter's footprint, the
estimate and their ratio.

    python benchmarks/lmi_memory.py [sizes...]      (default 10 20 30 40)
"""

import subprocess
import sys

CHILD = r'''
import resource, sys, numpy as np, control as ct
import controlext as cx
from controlext.synthesis import plant_problem
from controlext.synthesis.lmi import lmi_memory, solve_observer_lmi
n = int(sys.argv[1])
rng = np.random.default_rng(0)
A = rng.normal(size=(n, n)) / np.sqrt(n) - 1.5 * np.eye(n)
prob = plant_problem(ct.ss(A, np.zeros((n, 1)), rng.normal(size=(2, n)), 0))
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
solve_observer_lmi(prob, cx.HalfPlane(0.5))
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(peak - base, lmi_memory(prob))
'''


def main(sizes):
    print(f"{'states':>6} {'measured MB':>12} {'estimate MB':>12} {'ratio':>6}")
    for n in sizes:
        out = subprocess.run([sys.executable, '-c', CHILD, str(n)],
                             capture_output=True, text=True, check=True)
        used, est = map(float, out.stdout.split())
        print(f"{n:6d} {used / 2**20:12.0f} {est / 2**20:12.0f} "
              f"{est / used:6.2f}")


if __name__ == '__main__':
    main([int(a) for a in sys.argv[1:]] or [10, 20, 30, 40])
