#!/usr/bin/env python3
"""Compare two methods of an `eomc bench` CSV at equal final error.

For each method the runs are reduced to their work-precision front: sorted by cost, keeping
only runs more accurate than every cheaper one. The cost needed for an error E is read off that
front by linear interpolation in log(cost) against log(error) between the two runs that bracket
E (no extrapolation). Costs are rhs evaluations and median wall seconds, each with its own front.

    python3 bench/compare_work_precision.py out/work_precision.csv dop853 runge_kutta_fehlberg78
"""

import argparse
import csv
import math


def front(rows, cost_key):
    points = sorted((float(r[cost_key]), float(r["error"])) for r in rows if float(r["error"]) > 0)
    out, best = [], math.inf
    for cost, err in points:
        if err < best:
            out.append((cost, err))
            best = err
    return out


def cost_at(points, error):
    """Cost to reach `error` on the front, interpolated in log-log; None outside its range."""
    for (c0, e0), (c1, e1) in zip(points, points[1:]):
        if e1 <= error <= e0:
            if e0 == e1:
                return c0
            f = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(c0) + f * (math.log(c1) - math.log(c0)))
    return None


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv")
    p.add_argument("method")
    p.add_argument("other")
    p.add_argument("--errors", default="1e-4,1e-6,1e-8,1e-9,1e-10,1e-11,5e-12,2.4e-12",
                   help="comma-separated error levels (default %(default)s)")
    a = p.parse_args()
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    sel = {m: [r for r in rows if r["method"] == m] for m in (a.method, a.other)}
    for m, rs in sel.items():
        if not rs:
            raise SystemExit(f"no rows for {m} in {a.csv}")
    fronts = {(m, k): front(rs, k) for m, rs in sel.items() for k in ("rhs_evals", "wall_seconds")}
    print(f"| error | {a.method} rhs | {a.other} rhs | ratio | {a.method} ms | {a.other} ms | ratio |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for e in (float(x) for x in a.errors.split(",")):
        n1, n2 = (cost_at(fronts[(m, "rhs_evals")], e) for m in (a.method, a.other))
        t1, t2 = (cost_at(fronts[(m, "wall_seconds")], e) for m in (a.method, a.other))
        fmt_n = lambda v: "-" if v is None else f"{v:.0f}"
        fmt_t = lambda v: "-" if v is None else f"{v * 1e3:.3f}"
        ratio = lambda x, y: "-" if x is None or y is None else f"{x / y:.2f}"
        print(f"| {e:.1e} | {fmt_n(n1)} | {fmt_n(n2)} | {ratio(n1, n2)} | {fmt_t(t1)} | {fmt_t(t2)} | {ratio(t1, t2)} |")


if __name__ == "__main__":
    main()
