#!/usr/bin/env python3
"""Every message with advice in the code base is listed in tests/hostile/ADVICE.md with the test
that follows it: prints each message not listed, or listed with a test that does not exist, and
exits 1. A message with advice: a string literal in the workspace's sources (tests left out) whose
text tells the user what to do ("; give ...", ": set ...", "try ...", "raise ...").

usage: scripts/check_advice.py [--list]   (--list: print the messages found, one a line)"""
import os, re, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VERBS = ("give|set|try|raise|lower|add|use|remove|delete|rebuild|place|move|check|reverse|flip|"
         "fill|fix|record|refine|enlarge|save|join|separate|run|pass|reduce|allow|put|rename|"
         "shorten|choose|replace|select")
ADVICE = re.compile(r"(?:[;:,.(?] |^)(?:" + VERBS + r")\b", re.I)
LITERAL = re.compile(r'"((?:[^"\\]|\\.)*)"')

def sources():
    dirs = [os.path.join(ROOT, "src")] + [
        os.path.join(ROOT, "crates", c, "src") for c in sorted(os.listdir(os.path.join(ROOT, "crates")))]
    for d in dirs:
        for dp, _, fns in os.walk(d):
            for f in sorted(fns):
                if f.endswith(".rs"):
                    yield os.path.join(dp, f)

def literals(text):
    """The string literals of Rust source with their lines: comments, char literals, lifetimes
    and raw strings are stepped over, so that quotes pair as the compiler pairs them."""
    i, n, out = 0, len(text), []
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            i = text.find("\n", i)
            i = n if i < 0 else i
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = n if j < 0 else j + 2
        elif c == "r" and re.match(r'r#*"', text[i:i + 10]) and not (i and (text[i - 1].isalnum() or text[i - 1] == "_")):
            hashes = re.match(r'r(#*)"', text[i:]).group(1)
            end = text.find('"' + hashes, i + 2 + len(hashes))
            end = n if end < 0 else end
            out.append((text[:i].count("\n") + 1, text[i + 2 + len(hashes):end]))
            i = end + 1 + len(hashes)
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append((text[:i].count("\n") + 1, text[i + 1:j]))
            i = j + 1
        elif c == "'":
            m = re.match(r"'(\\.|\\u\{[0-9a-fA-F]+\}|[^\\'])'", text[i:i + 12])
            i += len(m.group(0)) if m else 1
        else:
            i += 1
    return out


def messages():
    found = []
    for path in sources():
        text = open(path).read()
        cut = text.find("#[cfg(test)]")
        if cut >= 0:
            text = text[:cut]
        for line, s in literals(text):
            if ADVICE.search(s) and len(s) >= 12:
                found.append((os.path.relpath(path, ROOT), line, s))
    return found

def listed():
    rows = {}
    table = open(os.path.join(ROOT, "tests/hostile/ADVICE.md")).read()
    for line in table.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 3 and cells[0].startswith("`") and not cells[0].startswith("`file"):
            rows[cells[1].strip("`")] = cells[2]
    return rows

def tests_known():
    """Hostile cases that follow their advice (a `[case.followed]` run, or a case of their own
    named "the advice followed: ..."), and the workspace's function names."""
    text = open(os.path.join(ROOT, "tests/hostile/cases.toml")).read()
    names = set()
    for block in text.split("[[case]]")[1:]:
        m = re.search(r'^name = "(.*)"$', block, re.M)
        if m and ("[case.followed]" in block or m.group(1).startswith("the advice followed")):
            names.add(m.group(1).replace('\\"', '"'))
    fns = set()
    for dp, _, fns_ in os.walk(ROOT):
        if "/target" in dp or "/.git" in dp:
            continue
        for f in fns_:
            if f.endswith(".rs"):
                fns |= set(re.findall(r"fn (\w+)\(", open(os.path.join(dp, f), errors="replace").read()))
            elif f.endswith(".py"):
                fns |= set(re.findall(r"def (test_\w+)\(", open(os.path.join(dp, f), errors="replace").read()))
    return names, fns

def main():
    found = messages()
    if "--list" in sys.argv:
        for path, line, s in found:
            print(f"{path}:{line}: {s[:160]}")
        return 0
    rows = listed()
    names, fns = tests_known()
    bad = 0
    for path, line, s in found:
        key = next((k for k in rows if k and k in s), None)
        if key is None:
            print(f"{path}:{line}: not in tests/hostile/ADVICE.md: {s[:120]}")
            bad += 1
            continue
        test = rows[key]
        ok = (test.startswith("case: ") and test[6:].strip('"') in names) or (
            test.startswith("fn ") and test[3:].split(" (")[0].strip("`") in fns) or test.startswith("not followed")
        if not ok:
            print(f"{path}:{line}: its test is not found: {test}")
            bad += 1
    unfollowed = sum(1 for t in rows.values() if t.startswith("not followed"))
    print(f"{len(found)} messages with advice; {len(rows)} listed, {unfollowed} of them not followed by a test (the reason given)")
    return 1 if bad else 0

sys.exit(main())
