"""``python -m controlext``: reproduce Section IV of Li & Sanfelice."""

import argparse
import concurrent.futures
import contextlib
import os
import sys

from .paper import format_table, paper_rows
from .paper.designs import ROBUST, TABLE, run_designs, tradeoff_keys


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog='python -m controlext',
        description="Reproduce the published numbers of Li & Sanfelice, "
                    "'A coupled pair of Luenberger observers', Section IV.")
    parser.add_argument('--no-synthesis', action='store_true',
                        help="only evaluate the published gains (fast); "
                             "skip controlext's own designs")
    parser.add_argument('--out', default='controlext-paper',
                        help='folder for the figures (default: %(default)s)')
    parser.add_argument('--no-figures', action='store_true',
                        help='print the table only')
    parser.add_argument('--workers', type=int, default=None,
                        help='processes for the independent designs '
                             '(default: one per core, at most 4; 1: none)')
    args = parser.parse_args(argv)
    workers = args.workers if args.workers is not None else \
        min(4, os.cpu_count() or 1)
    if workers < 1:
        parser.error(f"--workers must be at least 1; found {workers}")
    print("Li & Sanfelice, Section IV: published numbers and "
          "controlext's", flush=True)
    with contextlib.ExitStack() as stack:
        executor = None if workers == 1 else stack.enter_context(
            concurrent.futures.ProcessPoolExecutor(workers))
        designs = None
        if not args.no_synthesis:
            # the table's designs and the figures' in one batch
            keys = TABLE + ROBUST + ([] if args.no_figures else
                                     tradeoff_keys())
            print(f"designing {len(keys)} observers on {workers} "
                  f"process{'es' if workers > 1 else ''} (about 40 s on two "
                  "cores) ...", flush=True)
            designs = run_designs(keys, executor)
        rows = paper_rows(synthesise=not args.no_synthesis, designs=designs)
        print(format_table(rows))
        if not args.no_figures:
            from .paper.figures import write_all
            paths = write_all(args.out, executor=executor,
                              designs=designs)
            print(f"\nfigures written to {args.out}/:")
            for path in paths:
                print(f"  {path}")
    bad = [r for r in rows if not r.ok]
    if bad:
        print(f"\n{len(bad)} row(s) do not match the published value",
              file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
