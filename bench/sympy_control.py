#!/usr/bin/env python3
"""eomc's program controls (Mei ch. 3) against an independent SymPy construction.

For each scene, from its TOML alone: M = ∂²T/∂q̇², f = ∂L/∂q − (∂²L/∂q̇∂q) q̇; each program row by
Erugin's construction with Galiullin's gains (Galiullin, Inverse Problems of Dynamics, 1981;
Erugin, PMM 16, 1952): a configuration program ω has ω̈ = ∇ω q̈ + a, c = −a − 2αω̇ − β²ω; a phase
program φ has φ̇ = (∂φ/∂q̇) q̈ + b, c = −b − κφ; D = Āᵀ (ideal, Chetaev for φ) or unit columns
(actuated); λ = (Ā M⁻¹ D)⁻¹ (c − Ā M⁻¹ f), Q_c = D λ. `eomc control SCENE --format json` gives its
own λ and Q_c in closed form. Both are compared symbolically (sympy.simplify of the difference) and
at random states; the largest relative difference is printed.

Usage: python3 bench/sympy_control.py [path/to/eomc] [scene.toml ...]
   (default scenes: scenes/meshchersky_circle.toml scenes/two_link_arm.toml scenes/attitude_slew.toml)
"""
import json
import random
import subprocess
import sys
import time
import tomllib

import sympy as sp

EOMC = sys.argv[1] if len(sys.argv) > 1 else "build/generator/eomc"
SCENES = sys.argv[2:] or ["scenes/meshchersky_circle.toml", "scenes/two_link_arm.toml", "scenes/attitude_slew.toml"]


def parse(text, names):
    return sp.sympify(text.replace("^", "**"), locals=names)


def sympy_control(scene):
    t = sp.Symbol("t")
    names = {"t": t}
    for p in scene.get("parameters", {}):
        names[p] = sp.Symbol(p)
    coords = list(scene["coordinates"])
    q = [sp.Symbol(c) for c in coords]
    u = [sp.Symbol(c + "_dot") for c in coords]
    for s in q + u:
        names[str(s)] = s
    T = parse(scene["lagrangian"]["T"], names)
    V = parse(scene["lagrangian"].get("V", "0"), names)
    L = T - V
    n = len(q)
    M = sp.Matrix(n, n, lambda i, j: sp.diff(T, u[i], u[j]))
    f = sp.Matrix([sp.diff(L, q[i]) - sum(sp.diff(L, u[i], q[j]) * u[j] for j in range(n)) - sp.diff(L, u[i], t)
                   for i in range(n)])
    rows, targets, columns, column_names = [], [], [], []
    for p in scene["program"]:
        e = parse(p["constraint"], names)
        law = {k: sp.nsimplify(v) for k, v in p.get("erugin", {}).items()}  # exact gains
        if any(e.has(v) for v in u):  # phase program φ(q, q̇, t)
            W = [sp.diff(e, v) for v in u]
            b = sum(sp.diff(e, q[j]) * u[j] for j in range(n)) + sp.diff(e, t)
            c = -b - law.get("kappa", 0) * e
        else:  # configuration program ω(q, t)
            grad = [sp.diff(e, x) for x in q]
            rate = sum(grad[j] * u[j] for j in range(n)) + sp.diff(e, t)
            W = grad
            a = sum(sp.diff(rate, q[j]) * u[j] for j in range(n)) + sp.diff(rate, t)
            c = -a - 2 * law.get("alpha", 0) * rate - law.get("beta", 0) ** 2 * e
        rows.append(W)
        targets.append(c)
        control = p.get("control", "ideal")
        if control == "ideal":
            columns.append(W)
            column_names.append("lambda_" + p["name"])
        else:  # actuated coordinates
            for k in control:
                columns.append([1 if x == k else 0 for x in coords])
                column_names.append("lambda_" + p["name"] if len(control) == 1 else f"lambda_{p['name']}_{k}")
    A = sp.Matrix(rows)
    D = sp.Matrix(columns).T
    Minv = M.inv()
    lam = (A * Minv * D).inv() * (sp.Matrix(targets) - A * Minv * f)
    lam = [sp.simplify(x) for x in lam]
    Qc = [sp.simplify(x) for x in D * sp.Matrix(lam)]
    return names, q + u, dict(zip(column_names, lam)), Qc


def sympy_rigid_control(scene):
    """A free rigid body in the quaternion formulation (Mei §3.2), programs on ω = (p, q, r) and the
    attitude e (body → space): M = I, f = Iω × ω, ė = ½ e ⊗ (0, ω); a program ω(e, t) reaches ω̇ at
    its second derivative, φ(ω, e, t) at its first; D's columns are the body-axis torques."""
    body = scene["rigid_body"]
    assert body.get("weight", "0") == "0" and "gyrostatic_moment" not in body, "a free body only"
    t = sp.Symbol("t")
    names = {"t": t}
    for p in scene.get("parameters", {}):
        names[p] = sp.Symbol(p)
    w = sp.symbols("p q r")
    e = sp.symbols("e0 e1 e2 e3")
    for s in w + e:
        names[str(s)] = s
    inertia = [parse(x, names) for x in body["inertia"]]
    M = sp.diag(*inertia) if len(inertia) == 3 else sp.Matrix(3, 3, inertia)
    omega = sp.Matrix(w)
    f = (M * omega).cross(omega)
    half = sp.Rational(1, 2)
    e_rate = [-half * (e[1] * w[0] + e[2] * w[1] + e[3] * w[2]), half * (e[0] * w[0] + e[2] * w[2] - e[3] * w[1]),
              half * (e[0] * w[1] + e[3] * w[0] - e[1] * w[2]), half * (e[0] * w[2] + e[1] * w[1] - e[2] * w[0])]

    def along(h):  # dh/dt with ω held: ∂h/∂t + ∂h/∂e ė
        return sp.expand(sp.diff(h, t) + sum(sp.diff(h, e[k]) * e_rate[k] for k in range(4)))

    rows, targets, columns, column_names = [], [], [], []
    for p in scene["program"]:
        x = parse(p["constraint"], names)
        law = {k: sp.nsimplify(v) for k, v in p.get("erugin", {}).items()}
        if any(x.has(v) for v in w):  # phase program φ(ω, e, t)
            rows.append([sp.diff(x, v) for v in w])
            targets.append(-along(x) - law.get("kappa", 0) * x)
        else:  # attitude program
            rate = along(x)
            rows.append([sp.diff(rate, v) for v in w])
            targets.append(-along(rate) - 2 * law.get("alpha", 0) * rate - law.get("beta", 0) ** 2 * x)
        columns.append([parse(str(m), names) for m in p["control"]["moment"]])
        column_names.append("lambda_" + p["name"])
    A = sp.Matrix(rows)
    D = sp.Matrix(columns).T
    Minv = M.inv()
    lam = (A * Minv * D).inv() * (sp.Matrix(targets) - A * Minv * f)
    lam = [sp.simplify(x) for x in lam]
    Qc = [sp.simplify(x) for x in D * sp.Matrix(lam)]
    # The torques at two states, at the scene's parameters (tests/mechanics/control quotes them).
    defaults = {names[k]: sp.nsimplify(v) for k, v in scene.get("parameters", {}).items()}
    for label, state in (("at rest, e = (cos 0.3, sin 0.3, 0, 0)",
                          {w[0]: 0, w[1]: 0, w[2]: 0, e[0]: sp.cos(sp.Rational(3, 10)), e[1]: sp.sin(sp.Rational(3, 10)),
                           e[2]: 0, e[3]: 0}),
                         ("omega = (0.3, -0.2, 0.7), e = (1, 1, -1, 1)/2",
                          {w[0]: sp.Rational(3, 10), w[1]: -sp.Rational(1, 5), w[2]: sp.Rational(7, 10),
                           e[0]: half, e[1]: half, e[2]: -half, e[3]: half})):
        print(f"  torques {label}: " + ", ".join(f"{sp.N(x.subs(defaults).subs(state), 16)}" for x in lam))
    return names, list(w) + list(e), dict(zip(column_names, lam)), Qc


def main():
    for path in SCENES:
        with open(path, "rb") as fh:
            scene = tomllib.load(fh)
        start = time.perf_counter()
        names, state, lam, Qc = (sympy_rigid_control if "rigid_body" in scene else sympy_control)(scene)
        sympy_s = time.perf_counter() - start
        command = [EOMC, "control", path, "--format", "json"]
        start = time.perf_counter()
        out = json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)
        eomc_s = time.perf_counter() - start
        ours = {}
        for p in out["programs"]:
            ours.update(p["lambda"])
        ours_Qc = list(out["Qc"].values())
        pairs = [(k, lam[k], parse(ours[k], names)) for k in lam]
        pairs += [(f"Qc[{i}]", Qc[i], parse(ours_Qc[i], names)) for i in range(len(Qc))]
        rng = random.Random(17)
        worst, symbolic = 0.0, True
        for name, theirs, mine in pairs:
            symbolic = symbolic and sp.simplify(theirs - mine) == 0
            for _ in range(20):
                values = {s: rng.uniform(0.3, 1.7) for s in names.values()}
                a, b = float(theirs.subs(values)), float(mine.subs(values))
                worst = max(worst, abs(a - b) / max(1.0, abs(a)))
        print(f"{scene['scene']['name']}: {len(pairs)} expressions (lambda, Q_c), symbolic difference zero: "
              f"{symbolic}, largest relative difference at 20 random states each: {worst:.2e} "
              f"(sympy {sympy_s:.2f} s, eomc control {eomc_s:.2f} s)")
        for name, theirs, _ in pairs:
            print(f"  {name} = {theirs}")
        assert symbolic and worst < 1e-12, path


if __name__ == "__main__":
    main()
