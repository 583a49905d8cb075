#!/usr/bin/env python3
"""An object file that must not call libm's transcendental functions.

  check_no_libm.py --object NAME --expect SYMBOL OBJECT...

Among the OBJECTs (a target's object files), the one whose file name is NAME is read with
`nm --undefined-only`. Exit 0 when it references none of libm's transcendental functions
(log, log1p, exp, pow, sin, ... and their float forms) and does reference SYMBOL (proof
that the symbols were read at all); 1 otherwise, naming the calls.
"""
import argparse
import os
import subprocess
import sys

LIBM = {"log", "log1p", "log2", "log10", "logb", "exp", "exp2", "exp10", "expm1", "pow", "cbrt",
        "sin", "cos", "tan", "sincos", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",
        "asinh", "acosh", "atanh", "lgamma", "lgamma_r", "tgamma", "erf", "erfc", "hypot"}


def libm_name(symbol):
    base = symbol.split("@", 1)[0]
    for name in (base, base.removeprefix("__"), base.removesuffix("_finite").removeprefix("__")):
        if name in LIBM or (name.endswith(("f", "l")) and name[:-1] in LIBM):
            return True
    return False


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--object", required=True)
    parser.add_argument("--expect", required=True)
    parser.add_argument("objects", nargs="+")
    args = parser.parse_args()
    matches = [o for o in args.objects if os.path.basename(o) == args.object]
    if len(matches) != 1:
        print(f"check_no_libm: {len(matches)} objects named {args.object} among {len(args.objects)}")
        return 1
    out = subprocess.run(["nm", "--undefined-only", matches[0]], capture_output=True, text=True, check=True).stdout
    symbols = [line.split()[-1] for line in out.splitlines() if line.strip()]
    calls = sorted(s for s in symbols if libm_name(s))
    if args.expect not in symbols:
        print(f"check_no_libm: {args.object} does not reference {args.expect}: were its symbols read? ({len(symbols)} found)")
        return 1
    if calls:
        print(f"check_no_libm: {args.object} calls libm: {', '.join(calls)}")
        return 1
    print(f"check_no_libm: {args.object}: {len(symbols)} undefined symbols, none from libm's transcendental functions")
    return 0


if __name__ == "__main__":
    sys.exit(main())
