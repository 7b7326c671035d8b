#!/usr/bin/env python3
"""Checks the shape of `eomc inverse --format json` (run by tests/mechanics/inverse/cli.cpp).

usage: check_inverse_json.py FILE N SELF_ADJOINT MULTIPLIER LAGRANGIAN
  N             number of coordinates
  SELF_ADJOINT  true | false | null (the expected verdict)
  MULTIPLIER    yes | no (an n×n multiplier expected)
  LAGRANGIAN    yes | no (a verified Lagrangian expected)
Exits non-zero with a message naming the first mismatch."""
import json
import sys


def fail(message):
    sys.exit(f"{sys.argv[1]}: {message}")


def main():
    path, n, self_adjoint, multiplier, lagrangian = sys.argv[1:6]
    n = int(n)
    with open(path, encoding="utf-8") as f:
        d = json.load(f)
    for key in ("form", "conditions", "self_adjoint", "multiplier", "lagrangian", "verified", "reason"):
        if key not in d:
            fail(f"missing key '{key}'")
    if d["form"] not in ("fundamental", "kinematic"):
        fail(f"form = {d['form']!r}")
    # Santilli's conditions: S1 (i<j), S2 (i; j<k), S3 (i≤j), S4 (i<j; k), S5 (i<j).
    pairs = n * (n - 1) // 2
    expected = {"S1": pairs, "S2": n * pairs, "S3": n * (n + 1) // 2, "S4": pairs * n, "S5": pairs}
    counts = {name: 0 for name in expected}
    for c in d["conditions"]:
        name = c.get("name")
        if name not in expected:
            fail(f"condition name {name!r}")
        counts[name] += 1
        for index in ("i", "j") + (("k",) if name in ("S2", "S4") else ()):
            if not isinstance(c.get(index), int) or not 0 <= c[index] < n:
                fail(f"{name}: index {index} = {c.get(index)!r}")
        if name not in ("S2", "S4") and "k" in c:
            fail(f"{name} has a third index")
        if not isinstance(c.get("residual"), str) or not c["residual"]:
            fail(f"{name}: residual {c.get('residual')!r}")
    if counts != expected:
        fail(f"condition counts {counts}, expected {expected}")
    want = {"true": True, "false": False, "null": None}[self_adjoint]
    if d["self_adjoint"] is not want:
        fail(f"self_adjoint = {d['self_adjoint']!r}, expected {want!r}")
    g = d["multiplier"]
    if multiplier == "yes":
        if not (isinstance(g, list) and len(g) == n and all(isinstance(r, list) and len(r) == n for r in g)
                and all(isinstance(e, str) for r in g for e in r)):
            fail(f"multiplier = {g!r}, expected an {n}x{n} matrix of expressions")
    elif g is not None:
        fail(f"multiplier = {g!r}, expected null")
    if lagrangian == "yes":
        if not isinstance(d["lagrangian"], str) or d["verified"] is not True:
            fail(f"lagrangian = {d['lagrangian']!r}, verified = {d['verified']!r}")
    elif d["lagrangian"] is not None or d["verified"] is not False:
        fail(f"lagrangian = {d['lagrangian']!r}, verified = {d['verified']!r}, expected none")
    if not isinstance(d["reason"], str) or not d["reason"]:
        fail("empty reason")


main()
