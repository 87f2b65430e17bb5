#!/usr/bin/env python3
"""Issue 56's acceptance measures from the case tables of `softgrip prove` reports (one seed's
cases may be run apart, `prove --only CASE`, one report each).

1. Effect classes named right among the effect cases above the model's own form-error band (the
   baseline's NRMSE before over the same experiment's controls' > 1.25, as
   `after_over_control.py` measures it), controls "none", out-of-catalogue cases "unexplained"
   at markers the hidden physics moves (the report's "right" column).
2. Where named: a region placed (the report's "(placed" mark); each recovered size within 30 %
   of the hidden value or within two of its standard errors; the baseline's E on the controls
   against the truth's (the report's own line).

Usage: scripts/prove_acceptance.py DIAGNOSIS.md [...]"""

import re
import sys
from collections import defaultdict

from after_over_control import floor, rows

SIZE = re.compile(r"(\w[\w /]*?) (-?\d+\.\d+) -> (-?\d+\.\d+)(?: \+/- (\d+\.\d+))?")


def cells_of(path):
    """Each case row's cells, by its case name and seed."""
    out = {}
    for line in open(path):
        c = [x.strip() for x in line.strip().strip("|").split("|")]
        if len(c) >= 11 and ", seed " in c[0]:
            name, seed = c[0].split(", seed ")
            out[(re.sub(r" \(.*\)$", "", name), seed)] = c
    return out


def main() -> None:
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    paths = sys.argv[1:]
    table = [r for p in paths for r in rows(p)]
    cells = {k: v for p in paths for k, v in cells_of(p).items()}
    control = defaultdict(dict)
    for r in table:
        if r["case"].startswith("control"):
            control[(r["seed"], r["model"])][r["case"]] = r
    t = defaultdict(lambda: [0, 0])
    lines = []
    for r in table:
        key = (r["case"], r["seed"])
        c = cells.get(key)
        if r["case"].startswith("control"):
            t["controls none"][0] += r["named"] == "none"
            t["controls none"][1] += 1
            continue
        if r["case"].startswith("unexplained"):
            t["out of catalogue: unexplained, placed"][0] += r["right"]
            t["out of catalogue: unexplained, placed"][1] += 1
            lines.append(f"| {r['case']} | {r['seed']} | {r['named'][:60]} | {'yes' if r['right'] else 'NO'} |")
            continue
        band = floor(r, control, "before")
        above = band is not None and r["before"] > 1.25 * band
        k = "effects above the band: named right" if above else "effects within the band: named right"
        t[k][0] += r["right"]
        t[k][1] += 1
        if c is None or not r["right"]:
            continue
        if "heterogeneous" in r["case"]:
            t["heterogeneous named: placed"][0] += "(placed" in c[8]
            t["heterogeneous named: placed"][1] += 1
        for m in SIZE.finditer(c[7]):
            name, hidden, got, se = m.group(1), float(m.group(2)), float(m.group(3)), m.group(4)
            err = abs(got - hidden)
            ok = err <= 0.3 * abs(hidden) or (se is not None and err <= 2 * float(se))
            t["sizes within 30 % or 2 s.e."][0] += ok
            t["sizes within 30 % or 2 s.e."][1] += 1
            if not ok:
                lines.append(f"| {r['case']} | {r['seed']} | {name} {hidden} -> {got} +/- {se} | off |")
    print("| measure | count | share |\n|---|---|---|")
    for k, (n, d) in t.items():
        print(f"| {k} | {n} of {d} | {100 * n / d:.0f} % |" if d else f"| {k} | 0 of 0 | - |")
    print("\n| case | seed | verdict or size | |\n|---|---|---|---|")
    print("\n".join(lines))
    for p in paths:
        for line in open(p):
            if line.startswith("The continuum baseline's E against the truth's"):
                print(f"\n{p}: {line.strip()}")


if __name__ == "__main__":
    main()
