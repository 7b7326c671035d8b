#!/usr/bin/env python3
"""Condenses a rigid-body work-precision CSV (bench/run_rigid_formulations.sh) into the table of
bench/RESULTS.md: per formulation, the best (ω, γ) error at t_end and the cheapest run (wall time,
any method, named) whose error is at most 1e-3, 1e-6 and 1e-9, with the energy drift of the run
quoted at 1e-6.

usage: condense_rigid_formulations.py WORK_PRECISION_CSV
"""
import csv
import math
import sys

LEVELS = (1e-3, 1e-6, 1e-9)


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    forms = list(dict.fromkeys(r["formulation"] for r in rows))
    print("| formulation | best error | to 1e-3: ms, rhs | to 1e-6: ms, rhs | to 1e-9: ms, rhs "
          "| energy drift of the 1e-6 run |")
    print("|---|---:|---:|---:|---:|---:|")
    for form in forms:
        ok = [r for r in rows if r["formulation"] == form and r["omega_gamma_error"] not in ("", "nan")
              and math.isfinite(float(r["omega_gamma_error"]))]
        if not ok:
            print(f"| {form} | — | — | — | — | — |")
            continue
        best = min(ok, key=lambda r: float(r["omega_gamma_error"]))
        cells, drift = [], "—"
        for level in LEVELS:
            reaching = [r for r in ok if float(r["omega_gamma_error"]) <= level]
            if not reaching:
                cells.append("—")
                continue
            r = min(reaching, key=lambda r: float(r["wall_seconds"]))
            cells.append(f"{float(r['wall_seconds']) * 1e3:.3g}, {r['rhs_evals']} ({r['method']})")
            if level == 1e-6:
                drift = f"{float(r['max_energy_drift']):.1e}"
        print(f"| {form} | {float(best['omega_gamma_error']):.2g} ({best['method']}) | " + " | ".join(cells)
              + f" | {drift} |")


if __name__ == "__main__":
    main()
