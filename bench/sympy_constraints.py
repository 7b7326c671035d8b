#!/usr/bin/env python3
"""eomc's constraint multipliers against SymPy's LagrangesMethod, side by side on one system.

For each system: `eomc derive --format json` gives λ in closed form; SymPy's
LagrangesMethod(L, q, hol_coneqs=…/nonhol_coneqs=…).solve_multipliers() gives its own. SymPy writes
the equations as d/dt ∂L/∂q̇ − ∂L/∂q + Σ λ ∂f/∂q = 0 and eomc as … = Σ λ ∂f/∂q, so
λ_eomc = −λ_sympy. Both are evaluated at random states and parameters and must agree to a few
ulps. Also times both (derivation only).

Usage: python3 bench/sympy_constraints.py [path/to/eomc]   (needs python3-sympy)
"""
import json
import random
import subprocess
import sys
import time

import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

EOMC = sys.argv[1] if len(sys.argv) > 1 else "build/generator/eomc"


def eomc_multipliers(scene):
    start = time.perf_counter()
    out = subprocess.run([EOMC, "derive", scene, "--format", "json"], check=True, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    rows = json.loads(out.stdout)["constraints"]
    return {r["name"]: r["lambda"] for r in rows}, elapsed


def compare(name, scene, coords, lagrangian, hol=(), nonhol=(), row_names=(), params=()):
    t = sp.Symbol("t")
    start = time.perf_counter()
    lm = LagrangesMethod(lagrangian, coords, hol_coneqs=list(hol), nonhol_coneqs=list(nonhol))
    lm.form_lagranges_equations()
    sol = lm.solve_multipliers()
    sympy_s = time.perf_counter() - start
    ours, eomc_s = eomc_multipliers(scene)
    # One plain symbol per coordinate, rate and parameter, as eomc's JSON names them.
    plain = {}
    for q in coords:
        n = str(q.func)
        plain[q.diff(t)] = sp.Symbol(n + "_dot")
        plain[q] = sp.Symbol(n)
    worst = 0.0
    rng = random.Random(5)
    for alpha, lam in enumerate(lm.lam_vec):
        theirs = (-sol[lam]).subs(plain)
        names = {str(s): s for s in list(plain.values()) + list(params)}  # "I" is a parameter, not √−1
        mine = sp.sympify(ours[row_names[alpha]].replace("^", "**"), locals=names)
        for _ in range(20):
            point = {s: sp.Float(rng.uniform(0.5, 1.5)) for s in list(plain.values()) + list(params)}
            a, b = complex(theirs.evalf(30, subs=point)), complex(mine.evalf(30, subs=point))
            worst = max(worst, abs(a - b) / max(1.0, abs(a)))
    print(f"| {name} | {len(lm.lam_vec)} | {worst:.1e} | {sympy_s:.3f} s | {eomc_s:.3f} s |")
    return worst


def main():
    t = sp.Symbol("t")
    print("| system | rows | max relative difference of λ (20 random points each) | SymPy LagrangesMethod | eomc derive |")
    print("|---|---|---|---|---|")
    m, g, l = sp.symbols("m g l")
    x, y = dynamicsymbols("x y")
    L = m * (x.diff(t) ** 2 + y.diff(t) ** 2) / 2 - m * g * y
    ok = compare("Cartesian pendulum", "scenes/pendulum_cartesian.toml", [x, y], L, hol=[x**2 + y**2 - l**2],
                 row_names=["rod"], params=[m, g, l]) < 1e-20
    M, I, a = sp.symbols("m I a")
    X, Y, phi = dynamicsymbols("x y phi")
    xd, yd, pd = X.diff(t), Y.diff(t), phi.diff(t)
    Ls = M * ((xd - a * sp.sin(phi) * pd) ** 2 + (yd + a * sp.cos(phi) * pd) ** 2) / 2 + I * pd**2 / 2
    ok &= compare("Chaplygin's sleigh", "scenes/chaplygin_sleigh.toml", [X, Y, phi], Ls,
                  nonhol=[-sp.sin(phi) * xd + sp.cos(phi) * yd], row_names=["knife_edge"], params=[M, I, a]) < 1e-20
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
