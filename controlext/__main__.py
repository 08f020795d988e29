"""``python -m controlext``: reproduce Section IV of Li & Sanfelice."""

import argparse
import sys

from .paper import format_table, paper_rows


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog='python -m controlext',
        description="Reproduce the published numbers of Li & Sanfelice, "
                    "'A coupled pair of Luenberger observers', Section IV.")
    parser.add_argument('--no-synthesis', action='store_true',
                        help="only evaluate the published gains (fast); "
                             "skip controlext's own designs")
    args = parser.parse_args(argv)
    rows = paper_rows(synthesise=not args.no_synthesis)
    print("Li & Sanfelice, Section IV: published numbers and controlext's")
    print(format_table(rows))
    bad = [r for r in rows if not r.ok]
    if bad:
        print(f"\n{len(bad)} row(s) do not match the published value",
              file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
