#!/usr/bin/env python3
"""The SymPy side of the n-link pendulum benchmark.

Builds the same system as bench/make_pendulum_scenes.py (point mass m_k at the end of a
massless rod l_k, angle th_k from the downward vertical, positions written in the inertial
frame N with y up, gravity -g N.y) with sympy.physics.mechanics, derives M q'' = f with
KanesMethod or LagrangesMethod, runs sympy.cse on (M, f), counts the operations left with
eomc's rules, and writes the cse'd M and f as a C++ function through sympy.ccode:

    void <name>(const double* x, const double* p, double* M, double* f)

x = (th1..thn, th1_dot..thn_dot), p in eomc's parameter order (g, m1, l1, m2, l2, ...),
M row-major n*n. What is compared is the n*n mass matrix and n-vector forcing, not
mass_matrix_full / forcing_full (those add the kinematic rows q' = u).

With --spatial the system is the 3-D chain of make_pendulum_scenes.py --form spatial: rod k
has direction (sin a_k cos b_k, sin b_k, -cos a_k cos b_k) in N (z up), gravity -g N.z, and
x = (a1, b1, ..., an, bn, a1_dot, b1_dot, ...): eomc's order for that scene.

usage: sympy_pendulum.py N --method kane|lagrange [--spatial] -o DIR [--function NAME]
prints one JSON object (timings, op counts, header path) on stdout.
"""
import argparse
import json
import pathlib
import time

import sympy as sp
from sympy.physics import mechanics as me


def parameter_symbols(n):
    # eomc lists parameters in scene order: g, then m_k, l_k per link.
    g = sp.Symbol("g")
    m = [sp.Symbol(f"m{k}") for k in range(1, n + 1)]
    l = [sp.Symbol(f"l{k}") for k in range(1, n + 1)]
    ordered = [g]
    for k in range(n):
        ordered += [m[k], l[k]]
    return g, m, l, ordered


def bobs(n, N, O, q, m, l):
    """Point masses at the link ends, positions as in the scene (in N, y up). Velocities are
    the positions' time derivatives, taken by SymPy as eomc takes them itself; KanesMethod
    replaces q' by u through its kinematic equations."""
    particles = []
    x = sp.Integer(0)
    y = sp.Integer(0)
    for k in range(n):
        x += l[k] * sp.sin(q[k])
        y += -l[k] * sp.cos(q[k])
        P = O.locatenew(f"P{k + 1}", x * N.x + y * N.y)
        P.set_vel(N, P.pos_from(O).dt(N))
        particles.append((me.Particle(f"bob{k + 1}", P, m[k]), y))
    return particles


def spatial_bobs(n, N, O, q, m, l):
    """The 3-D chain: q = (a1, b1, a2, b2, ...), positions as in the spatial scene, z up."""
    particles = []
    x = y = z = sp.Integer(0)
    for k in range(n):
        a, b = q[2 * k], q[2 * k + 1]
        x += l[k] * sp.sin(a) * sp.cos(b)
        y += l[k] * sp.sin(b)
        z += -l[k] * sp.cos(a) * sp.cos(b)
        P = O.locatenew(f"P{k + 1}", x * N.x + y * N.y + z * N.z)
        P.set_vel(N, P.pos_from(O).dt(N))
        particles.append((me.Particle(f"bob{k + 1}", P, m[k]), z))
    return particles


def coordinate_names(n, spatial):
    return [f"{c}{k}" for k in range(1, n + 1) for c in "ab"] if spatial else [f"th{k}" for k in range(1, n + 1)]


def derive_kane(n, spatial=False):
    g, m, l, _ = parameter_symbols(n)
    names = coordinate_names(n, spatial)
    q = list(me.dynamicsymbols(",".join(names) + ","))
    u = list(me.dynamicsymbols(",".join(f"u_{c}" for c in names) + ","))
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    parts = (spatial_bobs if spatial else bobs)(n, N, O, q, m, l)
    up = N.z if spatial else N.y
    forces = [(p.point, -p.mass * g * up) for p, _ in parts]
    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[qi.diff() - ui for qi, ui in zip(q, u)])
    kane.kanes_equations([p for p, _ in parts], forces)
    M, f = kane.mass_matrix, kane.forcing   # M u' = f with u = q'
    return M, f, q, u


def derive_lagrange(n, spatial=False):
    g, m, l, _ = parameter_symbols(n)
    q = list(me.dynamicsymbols(",".join(coordinate_names(n, spatial)) + ","))
    qd = [qi.diff() for qi in q]
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    parts = (spatial_bobs if spatial else bobs)(n, N, O, q, m, l)
    for p, y in parts:
        p.potential_energy = p.mass * g * y   # V = g * sum m_k y_k, y up
    L = me.Lagrangian(N, *[p for p, _ in parts])
    lm = me.LagrangesMethod(L, q, frame=N)
    lm.form_lagranges_equations()
    M, f = lm.mass_matrix, lm.forcing       # M q'' = f
    return M, f, q, qd


def to_plain_symbols(exprs, q, speeds):
    """th_k(t) -> th_k, speed_k -> th_k_dot: the names eomc's kernel uses for x."""
    th = [sp.Symbol(qi.func.__name__) for qi in q]
    thd = [sp.Symbol(f"{qi.func.__name__}_dot") for qi in q]
    # xreplace looks at a node before its children, so Derivative(th_k(t), t) is replaced
    # whole before th_k(t) inside it would be.
    rep = {s: d for s, d in zip(speeds, thd)}
    rep.update({qi: t for qi, t in zip(q, th)})
    return [e.xreplace(rep) for e in exprs], th, thd


def count_operations(e, memo):
    """Operations of a SymPy tree by eomc's rules (generator/codegen/kernel_ir.hpp):
    + - * / one each; an integer power |k| costs |k|-1 multiplications plus one division
    when k < 0; a factor -1 is a sign absorbed by the subtraction it ends up in (0 ops);
    any other power, sqrt and every function call one each. SymPy and GiNaC share the
    shapes that matter: a - b is Add(a, Mul(-1, b)) and a / b is Mul(a, Pow(b, -1))."""
    if e.is_Atom:
        return 0
    if e in memo:
        return memo[e]
    ops = sum(count_operations(a, memo) for a in e.args)
    if e.is_Add:
        ops += len(e.args) - 1
    elif e.is_Mul:
        factors = sum(1 for a in e.args if a != -1)
        ops += max(factors - 1, 0)
    elif e.is_Pow and e.exp.is_Integer:
        k = int(e.exp)
        ops += max(abs(k) - 1, 0) + (1 if k < 0 else 0)
    else:
        ops += 1
    memo[e] = ops
    return ops


def emit_header(path, function, n, params, th, thd, temps, M_out, f_out, method):
    lines = [
        f"// Generated by bench/sympy_pendulum.py (SymPy {sp.__version__}, {method}) for the",
        f"// {n}-link pendulum: sympy.cse of M and f, printed by sympy.ccode. Do not edit.",
        "#pragma once",
        "#include <cmath>",
        "",
        f"inline constexpr const char* {function}_parameter_names[] = {{"
        + ", ".join(f'"{s}"' for s in params) + "};",
        "",
        f"inline void {function}(const double* x, const double* p, double* M, double* f) {{",
    ]
    for i, s in enumerate(th + thd):
        lines.append(f"    const double {s} = x[{i}];")
    for i, s in enumerate(params):
        lines.append(f"    const double {s} = p[{i}];")
    for s, v in temps:
        lines.append(f"    const double {s} = {sp.ccode(v)};")
    for i, v in enumerate(M_out):
        lines.append(f"    M[{i}] = {sp.ccode(v)};")
    for i, v in enumerate(f_out):
        lines.append(f"    f[{i}] = {sp.ccode(v)};")
    lines += ["}", ""]
    path.write_text("\n".join(lines))


def run(n, method, out_dir, function, spatial=False):
    derive = derive_kane if method == "kane" else derive_lagrange
    t0 = time.perf_counter()
    M, f, q, speeds = derive(n, spatial)
    t_derive = time.perf_counter() - t0

    exprs = list(M) + list(f)   # row-major M, then f
    t0 = time.perf_counter()
    plain, th, thd = to_plain_symbols(exprs, q, speeds)
    # cse's own default symbols are x0, x1, ...; x is the state pointer in the C++, so
    # name the temporaries w0, w1, ... instead.
    temps, reduced = sp.cse(plain, symbols=sp.numbered_symbols("w"))
    t_cse = time.perf_counter() - t0

    memo = {}
    ops_before = sum(count_operations(e, memo) for e in plain)
    ops_after = sum(count_operations(v, memo) for _, v in temps) + sum(count_operations(e, memo) for e in reduced)

    _, _, _, params = parameter_symbols(n)
    out_dir.mkdir(parents=True, exist_ok=True)
    header = out_dir / f"{function}_{n}.hpp"
    nq = len(q)
    emit_header(header, function, n, [str(s) for s in params], th, thd, temps,
                reduced[: nq * nq], reduced[nq * nq:], method)
    return {
        "n": n, "method": method, "sympy": sp.__version__,
        "derive_s": t_derive, "cse_s": t_cse,
        "ops_before": ops_before, "ops_after": ops_after, "temporaries": len(temps),
        "header": str(header), "function": function,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("n", type=int)
    ap.add_argument("--method", choices=["kane", "lagrange"], default="kane")
    ap.add_argument("--spatial", action="store_true", help="the 3-D chain (2n coordinates)")
    ap.add_argument("-o", "--output-dir", type=pathlib.Path, default=pathlib.Path("."))
    ap.add_argument("--function", help="C++ function name (default sympy_mass_forcing for kane, "
                                        "sympy_lagrange_mass_forcing for lagrange)")
    a = ap.parse_args()
    function = a.function or ("sympy_mass_forcing" if a.method == "kane" else "sympy_lagrange_mass_forcing")
    print(json.dumps(run(a.n, a.method, a.output_dir, function, a.spatial)))


if __name__ == "__main__":
    main()
