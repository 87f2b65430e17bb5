#!/usr/bin/env python3
"""Adds up the headline tables of several `softgrip prove` reports: one seed's cases run apart
(`prove --only CASE`, on several machines or after a stopped run) make one report each, and
their "X of Y" cells sum exactly. Seconds a verdict: the mean weighted by verdicts, the largest
max. Prints the summed table per model, in the reports' own columns, and the commits the
reports were built from (they should be one rule set).

Usage: scripts/prove_tally.py DIAGNOSIS.md [...]"""

import re
import sys
from collections import defaultdict

OF = re.compile(r"^(\d+) of (\d+)")


def headline(path):
    """The headline table's header and its rows, and the commit the report names."""
    lines = open(path).read().splitlines()
    commit = next((m.group(1) for l in lines if (m := re.search(r"commit `([0-9a-f]+)`", l))), "?")
    for i, line in enumerate(lines):
        if line.startswith("| model | effects named right"):
            header = [c.strip() for c in line.strip("|").split("|")]
            body = []
            for row in lines[i + 2:]:
                if not row.startswith("|"):
                    break
                body.append([c.strip() for c in row.strip("|").split("|")])
            return header, body, commit
    sys.exit(f"{path}: no headline table (a `softgrip prove` report starts with one)")


def main() -> None:
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    header, sums, seconds, commits = None, defaultdict(dict), defaultdict(list), set()
    shared = set()  # the columns whose cells print a share
    for path in sys.argv[1:]:
        h, body, commit = headline(path)
        commits.add(commit)
        if header is None:
            header = h
        elif h != header:
            sys.exit(f"{path}: its headline's columns differ from {sys.argv[1]}'s")
        for row in body:
            model, verdicts = row[0], None
            for col, cell in zip(header[1:], row[1:]):
                if m := OF.match(cell):
                    x, y = int(m.group(1)), int(m.group(2))
                    if cell.endswith("%)"):
                        shared.add(col)
                    a, b = sums[model].get(col, (0, 0))
                    sums[model][col] = (a + x, b + y)
                    if col.startswith("verdicts"):
                        verdicts = y
                elif col.startswith("seconds"):
                    mean, top = (float(v) for v in cell.split(","))
                    seconds[model].append((mean, top, verdicts))
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for model, cols in sums.items():
        cells = [model]
        for col in header[1:]:
            if col in cols:
                x, y = cols[col]
                share = f" ({round(100 * x / y) if y else 0} %)" if col in shared else ""
                cells.append(f"{x} of {y}{share}")
            elif col.startswith("seconds"):
                s = seconds[model]
                n = sum(v or 0 for _, _, v in s)
                mean = sum(m * (v or 0) for m, _, v in s) / n if n else 0.0
                cells.append(f"{mean:.0f}, {max(t for _, t, _ in s):.0f}")
            else:
                cells.append("?")
        print("| " + " | ".join(cells) + " |")
    print(f"\nbuilt from commit(s): {', '.join(sorted(commits))}; {len(sys.argv) - 1} reports")


if __name__ == "__main__":
    main()
