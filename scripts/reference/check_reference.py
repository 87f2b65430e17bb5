"""Checks that scripts/reference/ngsolve_reference.py still reproduces the committed reference.

Run by .ci/run on the cheapest problem (`hanging`, about 25 s): the figures just computed in DIR
must equal tests/reference/ngsolve.json's to the 6 significant digits the script writes.
Usage: python3 scripts/reference/check_reference.py DIR PROBLEM
"""
import json
import os
import sys


def figures(node, path=""):
    """Every number under node, by its path, leaving out timings and dates."""
    if isinstance(node, dict):
        for key, value in node.items():
            if key in ("seconds", "run_seconds", "last_run_seconds", "date"):
                continue
            yield from figures(value, f"{path}/{key}")
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from figures(value, f"{path}[{i}]")
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        yield path, float(node)


def main():
    out, problem = sys.argv[1], sys.argv[2]
    here = os.path.dirname(os.path.abspath(__file__))
    committed_path = os.path.join(here, "..", "..", "tests", "reference", "ngsolve.json")
    with open(committed_path) as f:
        committed = dict(figures(json.load(f)["problems"][problem]))
    with open(os.path.join(out, "ngsolve.json")) as f:
        fresh = dict(figures(json.load(f)["problems"][problem]))
    bad = [
        (p, committed.get(p), fresh.get(p))
        for p in sorted(set(committed) | set(fresh))
        if committed.get(p) is None
        or fresh.get(p) is None
        or abs(committed[p] - fresh[p]) > 1e-5 * max(abs(committed[p]), 1e-300)
    ]
    if bad:
        for p, c, n in bad[:20]:
            print(f"{problem}{p}: committed {c}, computed {n}")
        sys.exit(f"{len(bad)} figure(s) of '{problem}' differ from tests/reference/ngsolve.json")
    print(f"{problem}: {len(committed)} figures reproduce tests/reference/ngsolve.json")


if __name__ == "__main__":
    main()
