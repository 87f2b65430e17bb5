#!/usr/bin/env python3
"""Issue 37's "after" measure against the model's own floor: each named effect case's
after / the truth itself, over that of its experiment's controls of the same seed and model
(the sphere's two quasi-static controls, averaged; the time series from rest; the plate). A
control's ratio is the diagnosis model's form error against the finer truth with nothing hidden,
so a case within 1.25 x of it is as close as the model gets. Reads the case tables of one or
more DIAGNOSIS.md files (`softgrip prove`); prints a row per case and the share within 1.25 x.

Then the same band for detection: an effect case whose baseline (before) is within 1.25 x its
controls' is one the model's own form error could have made; the share named right is printed
for the effects above the band and within it, by seed.

Usage: scripts/after_over_control.py DIAGNOSIS.md [...]"""

import re
import sys
from collections import defaultdict

# The controls each effect case is measured against (same experiment, same kind of recording).
CONTROLS = {
    "finger-friction": ["control-plate"],
    "viscoelastic-creep": ["control-time-series"],
}
SPHERE = ["control-1", "control-2"]


def rows(path):
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 11 or not re.match(r"\d+\.\d+, \d+\.\d+$", cells[6]):
            continue
        name, seed = (cells[0].split(", seed ") + ["first"])[:2]
        name = re.sub(r" \(.*\)$", "", name)
        before, after = (float(x) for x in cells[6].split(","))
        moved = re.search(r"(\d+\.\d+) mm", cells[5])
        yield {
            "case": name, "seed": seed, "model": cells[1], "named": cells[3],
            "right": cells[4] == "yes", "before": before, "after": after,
            "moved": float(moved.group(1)) if moved else 0.0,
        }


def floor(r, control, key):
    """The mean `key` (before or after) of the case's experiment's controls, same seed and model;
    None when one of them was not run."""
    family = next((f for f in CONTROLS if r["case"].startswith(f)), None)
    mine = [control[(r["seed"], r["model"])].get(n) for n in (CONTROLS[family] if family else SPHERE)]
    return None if None in mine else sum(c[key] for c in mine) / len(mine)


def main() -> None:
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    table = [r for p in sys.argv[1:] for r in rows(p)]
    control = defaultdict(dict)
    for r in table:
        if r["case"].startswith("control"):
            control[(r["seed"], r["model"])][r["case"]] = r
    within = counted = 0
    print("| case | seed | model | after / truth | control's | ratio | within 1.25 x |")
    print("|---|---|---|---|---|---|---|")
    for r in table:
        # Named right, above the noise (moves a marker by more than twice its 0.1 mm).
        if r["case"].startswith("control") or r["named"] == "none" or r["moved"] <= 0.2:
            continue
        band = floor(r, control, "after")
        if band is None:
            print(f"| {r['case']} | {r['seed']} | {r['model']} | {r['after']:.2f} | not run | | |")
            continue
        ok = r["after"] <= 1.25 * band
        within += ok
        counted += 1
        print(f"| {r['case']} | {r['seed']} | {r['model']} | {r['after']:.2f} | {band:.2f} | "
              f"{r['after'] / band:.2f} | {'yes' if ok else 'no'} |")
    if counted:
        print(f"\nwithin 1.25 x the control's: {within} of {counted} ({100 * within / counted:.0f} %)")
    detection(table, control)


def detection(table, control) -> None:
    """Named right among the effects above the controls' band (before > 1.25 x the controls'
    before: the baseline's misfit on both sides) and within it."""
    tally = defaultdict(lambda: [0, 0, 0, 0])  # (seed, model): named above, above, named within, within
    print("\n| case | seed | model | named right | before / truth | control's | ratio | above the band |")
    print("|---|---|---|---|---|---|---|---|")
    for r in table:
        if r["case"].startswith("control"):
            continue
        band = floor(r, control, "before")
        if band is None:
            print(f"| {r['case']} | {r['seed']} | {r['model']} | {'yes' if r['right'] else 'NO'} | "
                  f"{r['before']:.2f} | not run | | |")
            continue
        above = r["before"] > 1.25 * band
        t = tally[(r["seed"], r["model"])]
        t[0 if above else 2] += r["right"]
        t[1 if above else 3] += 1
        print(f"| {r['case']} | {r['seed']} | {r['model']} | {'yes' if r['right'] else 'NO'} | "
              f"{r['before']:.2f} | {band:.2f} | {r['before'] / band:.2f} | {'yes' if above else 'no'} |")
    for (seed, model), (na, a, nw, w) in sorted(tally.items()):
        print(f"seed {seed}, {model}: named right {na} of {a} above the band, {nw} of {w} within it")


if __name__ == "__main__":
    main()
