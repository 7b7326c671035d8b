#!/usr/bin/env python3
"""Condenses an orbit-formulation work-precision CSV (bench/run_orbit_formulations.sh) into the
table of bench/RESULTS.md: per formulation, the best position error (km) and the cheapest run (wall
time, any method) whose error is at most 1 km, 1 m and 1 mm.

usage: condense_orbit_formulations.py WORK_PRECISION_CSV
"""
import csv,sys,math
rows=list(csv.DictReader(open(sys.argv[1])))
forms=[]
for r in rows:
    if r['formulation'] not in forms: forms.append(r['formulation'])
def fmt(x):
    return f"{x:.3g}"
print("| formulation | best error (km) | to 1 km: ms, rhs | to 1 m: ms, rhs | to 1 mm: ms, rhs |")
print("|---|---:|---:|---:|---:|")
for f in forms:
    rs=[r for r in rows if r['formulation']==f]
    ok=[r for r in rs if r['position_error'] not in ('','nan') and math.isfinite(float(r['position_error']))]
    best=min(ok,key=lambda r: float(r['position_error']))
    cells=[]
    for lvl in (1.0,1e-3,1e-6):
        c=[r for r in ok if float(r['position_error'])<=lvl]
        if not c: cells.append("—"); continue
        r=min(c,key=lambda r: float(r['wall_seconds']))
        cells.append(f"{fmt(float(r['wall_seconds'])*1e3)}, {r['rhs_evals']} ({r['method']})")
    print(f"| {f} | {float(best['position_error']):.2g} ({best['method']}) | "+" | ".join(cells)+" |")
