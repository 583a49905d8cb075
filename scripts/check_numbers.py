#!/usr/bin/env python3
"""Numbers in the docs that a command regenerates, checked against what it regenerates.

A marked number is followed, on the same line, by an HTML comment (invisible when the
Markdown is rendered) that names its source:

    ... 44 <!-- regen: run scenes/paper-direct-100.json :: manifest.json :: "connected": (\\d+) --> ...

  regen: SOURCE :: FILE :: REGEX   (" :: ", not "|", which would split a Markdown table's cell)
    SOURCE  `run SCENE [ARGS]`        axonguide run SCENE ARGS into a scratch folder
            `validate STUDY --quick`  the quick report (ctest validate.quick.STUDY writes it)
            `validate STUDY`          the full report (ctest -L validation writes it)
    FILE    a file of that run folder, or of the study's report folder
    REGEX   a Python regular expression with one group: its first match is the number

The number is the last one before the comment on its line; it must equal the group's text
(thousands separators and the typographic minus aside).

  check_numbers.py --binary AXONGUIDE --source DIR --reports DIR --kind quick|full DOC...
      exit 0 when every marker of that kind holds, 1 when one does not or none was found
  check_numbers.py --self-test    a wrong marker must be caught, a right one must pass
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile

MARKER = re.compile(r"<!--\s*regen:\s*(.*?)\s*-->")
NUMBER = re.compile(r"[-−]?\d[\d,]*(?:\.\d+)?(?:[eE][-+]?\d+)?")


def normal(text):
    return text.replace(",", "").replace("−", "-")


def markers(path):
    """(line number, number before the marker, source, file, regex) of every marker."""
    out = []
    for n, line in enumerate(open(path, encoding="utf-8"), 1):
        for m in MARKER.finditer(line):
            parts = [p.strip() for p in m.group(1).split(" :: ", 2)]
            before = NUMBER.findall(MARKER.sub("", line[: m.start()]))
            out.append((n, before[-1] if before else None, *(parts + [""] * (3 - len(parts)))))
    return out


def kind_of(source):
    words = source.split()
    if words[:1] == ["run"]:
        return "quick"  # a run is cheap: checked with the quick reports
    if words[:1] == ["validate"]:
        return "quick" if "--quick" in words else "full"
    return None


def regenerate(source, name, binary, src, reports, runs):
    """The text of FILE from SOURCE (each run made once)."""
    words = shlex.split(source)
    if words[0] == "run":
        key = " ".join(words[1:])
        if key not in runs:
            out = tempfile.mkdtemp(prefix="axg-numbers-")
            args = [binary, "run", os.path.join(src, words[1]), *words[2:], "--out", out, "-q"]
            r = subprocess.run(args, capture_output=True, text=True)
            if r.returncode != 0:
                raise RuntimeError(f"{' '.join(args)} exited {r.returncode}: {r.stderr.strip()[:300]}")
            runs[key] = out
        return open(os.path.join(runs[key], name), encoding="utf-8").read()
    return open(os.path.join(reports, words[1], name), encoding="utf-8").read()


def check(docs, binary, src, reports, kind):
    runs, problems, checked = {}, [], 0
    for doc in docs:
        for line, number, source, name, regex in markers(doc):
            where = f"{doc}:{line}"
            k = kind_of(source)
            if k is None or not name or not regex:
                problems.append(f"{where}: malformed marker (regen: SOURCE :: FILE :: REGEX): {source!r}")
                continue
            if k != kind:
                continue
            checked += 1
            if number is None:
                problems.append(f"{where}: no number before the marker")
                continue
            try:
                text = regenerate(source, name, binary, src, reports, runs)
            except (OSError, RuntimeError) as e:
                problems.append(f"{where}: {source} :: {name}: {e}")
                continue
            m = re.search(regex, text)
            if not m:
                problems.append(f"{where}: {regex!r} not found in {source} :: {name}")
            elif normal(m.group(1)) != normal(number):
                problems.append(f"{where}: the doc says {number}, {source} :: {name} gives {m.group(1)}")
    for p in problems:
        print(p)
    if checked == 0:
        print(f"no {kind} marker found in {', '.join(docs)}: nothing was checked")
        return 1
    print(f"{checked} marked number(s) of kind {kind}: {len(problems)} problem(s): {'FAIL' if problems else 'PASS'}")
    return 1 if problems else 0


def self_test():
    d = tempfile.mkdtemp(prefix="axg-numbers-self-")
    os.makedirs(os.path.join(d, "reports", "demo"))
    with open(os.path.join(d, "reports", "demo", "checks.csv"), "w") as f:
        f.write("check,measured\nthe answer,value = 1,234.5\n")
    good = os.path.join(d, "good.md")
    bad = os.path.join(d, "bad.md")
    marker = "<!-- regen: validate demo --quick :: checks.csv :: value = ([\\d,.]+) -->"
    with open(good, "w") as f:
        f.write(f"It is 1234.5 {marker} here.\n")
    with open(bad, "w") as f:
        f.write(f"It is 1234.6 {marker} here.\n")
    ok = check([good], "", d, os.path.join(d, "reports"), "quick") == 0
    caught = check([bad], "", d, os.path.join(d, "reports"), "quick") == 1
    print(f"self-test: right marker {'passes' if ok else 'FAILS'}, wrong marker {'caught' if caught else 'MISSED'}")
    return 0 if ok and caught else 1


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    opts, docs = {}, []
    i = 1
    while i < len(argv):
        if argv[i] in ("--binary", "--source", "--reports", "--kind") and i + 1 < len(argv):
            opts[argv[i][2:]] = argv[i + 1]
            i += 2
        else:
            docs.append(argv[i])
            i += 1
    if not docs or set(opts) != {"binary", "source", "reports", "kind"} or opts["kind"] not in ("quick", "full"):
        print(__doc__)
        return 2
    return check(docs, opts["binary"], opts["source"], opts["reports"], opts["kind"])


if __name__ == "__main__":
    sys.exit(main(sys.argv))
