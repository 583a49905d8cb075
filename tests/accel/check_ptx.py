#!/usr/bin/env python3
"""The floating-point contract of the device code (SPEC section 2), checked in its PTX.

  check_ptx.py FILE.ptx...            exit 0 when every file keeps the contract, 1 if not
  check_ptx.py --self-test SAMPLE.ptx exit 0 when exactly the lines marked "// BAD" are flagged

Three rules, each on an instruction's opcode (comments, directives and names are not read):
  1. no fma, and no mad on floating-point types (a fused multiply-add rounds once, the host
     twice);
  2. no .approx (rcp, sqrt, div, ex2, lg2, sin, cos: approximations the host does not make);
  3. every f64 add, sub, mul, div and sqrt carries .rn: the PTX ISA forbids ptxas to contract
     an add or mul with an explicit rounding mode into an fma, and requires one for f64 div
     and sqrt (IEEE round-to-nearest, as on the host).
"""
import re
import sys
from collections import Counter

# An optional label, an optional guard predicate, then opcode.qualifiers.
INSTRUCTION = re.compile(r"^(?:[$\w]+:\s*)?(?:@!?%\w+\s+)?([a-z][a-z0-9_]*)((?:\.[a-z0-9_]+)*)(?=[\s;]|$)")
FLOAT_TYPES = {"f16", "f16x2", "bf16", "bf16x2", "f32", "f64"}
ROUNDED = {"add", "sub", "mul", "div", "sqrt"}


def violations_and_counts(text):
    """(list of (line number, line, reason), Counter of opcode.type counts)."""
    bad, counts = [], Counter()
    in_block_comment = False
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw
        if in_block_comment:
            if "*/" not in line:
                continue
            line = line.split("*/", 1)[1]
            in_block_comment = False
        line = re.sub(r"/\*.*?\*/", " ", line)
        if "/*" in line:
            line, in_block_comment = line.split("/*", 1)[0], True
        line = line.split("//", 1)[0].strip()
        if not line or line.startswith("."):
            continue
        m = INSTRUCTION.match(line)
        if not m:
            continue
        base, quals = m.group(1), [q for q in m.group(2).split(".") if q]
        types = [q for q in quals if q in FLOAT_TYPES]
        if types:
            counts[f"{base}{'.rn' if 'rn' in quals else ''}.{types[-1]}"] += 1
        if base == "fma":
            bad.append((number, raw.strip(), "fma: a fused multiply-add"))
        elif base == "mad" and types:
            bad.append((number, raw.strip(), "mad on a floating-point type: a fused multiply-add"))
        if "approx" in quals:
            bad.append((number, raw.strip(), ".approx: an approximation"))
        if base in ROUNDED and "f64" in quals and "rn" not in quals:
            bad.append((number, raw.strip(), f"f64 {base} without .rn: may be contracted or not IEEE-rounded"))
    return bad, counts


def report(path, bad, counts):
    f64 = {op: counts[f"{op}.rn.f64"] for op in sorted(ROUNDED)}
    any_rn = {op: sum(n for k, n in counts.items() if k.startswith(f"{op}.rn.")) for op in ("add", "mul")}
    print(f"{path}:")
    print("  f64 with .rn: " + ", ".join(f"{op}.rn {n:,}" for op, n in f64.items()))
    print(f"  every type with .rn: add.rn {any_rn['add']:,}, mul.rn {any_rn['mul']:,}")
    fma = sum(n for k, n in counts.items() if k.startswith("fma"))
    mad = sum(n for k, n in counts.items() if k.startswith("mad"))
    approx = sum(1 for _, _, why in bad if why.startswith(".approx"))
    print(f"  fma {fma:,}, floating-point mad {mad:,}, .approx {approx:,}, f64 without .rn "
          f"{sum(1 for _, _, why in bad if 'without .rn' in why):,}")
    for number, line, why in bad:
        print(f"  line {number}: {why}: {line}")


def main(argv):
    if len(argv) == 3 and argv[1] == "--self-test":
        text = open(argv[2], encoding="utf-8").read()
        bad, _ = violations_and_counts(text)
        flagged = {n for n, _, _ in bad}
        marked = {n for n, line in enumerate(text.splitlines(), 1) if "// BAD" in line}
        if not marked:
            print(f"{argv[2]}: no line is marked // BAD")
            return 2
        missed, wrong = sorted(marked - flagged), sorted(flagged - marked)
        for n in missed:
            print(f"{argv[2]}:{n}: a violation the checker missed")
        for n in wrong:
            print(f"{argv[2]}:{n}: flagged but not a violation")
        print(f"self-test: {len(marked & flagged)} of {len(marked)} marked violations flagged, "
              f"{len(wrong)} false alarm(s): {'PASS' if not missed and not wrong else 'FAIL'}")
        return 0 if not missed and not wrong else 1
    if len(argv) < 2 or argv[1].startswith("-"):
        print(__doc__)
        return 2
    failed = False
    for path in argv[1:]:
        bad, counts = violations_and_counts(open(path, encoding="utf-8").read())
        report(path, bad, counts)
        if not any(k.endswith(".f64") for k in counts):
            print("  no f64 arithmetic at all: nothing was checked (is this the accelerator's PTX?)")
            failed = True
        failed = failed or bool(bad)
    print(f"PTX floating-point contract: {'FAIL' if failed else 'PASS'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
