#!/usr/bin/env python3
"""Lists the functions of the library crates longer than a limit (default 100 lines).

A function runs from its `fn` line to the closing brace at the same indentation (rustfmt's
layout); nested closures and items count toward the function that holds them. Unit-test modules
(`#[cfg(test)]`) and the tests/ and benches/ folders are not library code and are skipped.
Exit 1 when any function is over the limit. Usage: scripts/check_function_length.py [LIMIT]
"""
import pathlib
import re
import sys

LIMIT = int(sys.argv[1]) if len(sys.argv) > 1 else 100
ROOTS = ["src", "crates/softgrip-core/src", "crates/softgrip-lab/src",
         "crates/softgrip-viewer/src", "crates/softgrip-py/src"]
FN = re.compile(r"^(\s*)(?:pub(?:\([^)]*\))?\s+)?(?:const\s+)?(?:async\s+)?(?:unsafe\s+)?"
                r"(?:extern\s+\"C\"\s+)?fn\s+(\w+)")


def functions(path):
    lines = path.read_text().splitlines()
    skip_until = -1
    i = 0
    while i < len(lines):
        line = lines[i]
        if i > skip_until and line.strip() == "#[cfg(test)]" and i + 1 < len(lines) \
                and re.match(r"^\s*(pub\s+)?mod\s+\w+\s*\{", lines[i + 1]):
            indent = re.match(r"^(\s*)", lines[i + 1]).group(1)
            end = next((j for j in range(i + 2, len(lines)) if lines[j] == indent + "}"), len(lines))
            i = end + 1
            continue
        m = FN.match(line)
        if m:
            indent = m.group(1)
            # a declaration without a body (trait item) ends with `;` before any `{`
            j = i
            while j < len(lines) and "{" not in lines[j] and not lines[j].rstrip().endswith(";"):
                j += 1
            if j < len(lines) and "{" in lines[j]:
                if lines[j].rstrip().endswith("}") and j == i:
                    yield m.group(2), i + 1, 1
                else:
                    end = next((k for k in range(j + 1, len(lines))
                                if lines[k] == indent + "}"), None)
                    if end is not None:
                        yield m.group(2), i + 1, end - i + 1
        i += 1


def main():
    root = pathlib.Path(__file__).resolve().parent.parent
    long = []
    for r in ROOTS:
        for path in sorted((root / r).rglob("*.rs")):
            for name, line, length in functions(path):
                if length > LIMIT:
                    long.append((length, f"{path.relative_to(root)}:{line}", name))
    for length, where, name in sorted(long, reverse=True):
        print(f"{length:5} {where} {name}")
    print(f"{len(long)} functions over {LIMIT} lines")
    return 1 if long else 0


if __name__ == "__main__":
    sys.exit(main())
