#!/usr/bin/env python3
"""Fails when README.md's results table differs from the one tools/dev/results.sh generated
into docs/RESULTS.md (between the README table markers of tools/dev/results_tables.py), naming
the rows that differ: a figure in the README then always is results.sh's output.

Usage: check_readme_results.py SOURCE_DIR"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_tables  # noqa: E402


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    src = sys.argv[1]
    paths = [os.path.join(src, "docs", "RESULTS.md"), os.path.join(src, "README.md")]
    generated, readme = (results_tables.block(open(p, encoding="utf-8").read(), p)
                         for p in paths)
    if generated == readme:
        rows = sum(1 for line in readme.splitlines() if line.startswith("| ")) - 1
        print(f"README.md's results table: {rows} rows, as docs/RESULTS.md generated them")
        return 0
    want, got = generated.strip().splitlines(), readme.strip().splitlines()
    print("README.md's results table differs from docs/RESULTS.md's generated one "
          "(tools/dev/results.sh --update-docs copies it):", file=sys.stderr)
    for line in got:
        if line not in want:
            print(f"  README:     {line}", file=sys.stderr)
    for line in want:
        if line not in got:
            print(f"  RESULTS.md: {line}", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
