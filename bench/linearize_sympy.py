#!/usr/bin/env python3
# SymPy's constrained linearisation (sympy.physics.mechanics: LagrangesMethod.linearize, the
# Linearizer of Peterson, Gede & Hubbard, Multibody Syst. Dyn. 33 (2015) 143-161) on the systems
# tests/mechanics/linearize/linearize.cpp checks `eomc linearize` against: the eigenvalues of A at
# each operating point, printed to 17 digits. Run: python3 bench/linearize_sympy.py
# (output recorded in bench/results/linearize_sympy.txt; SymPy 1.14).
import sympy as sp
import sympy.physics.mechanics as me


def eigenvalues(A):
    import mpmath
    mpmath.mp.dps = 30
    ev = [complex(z) for z in mpmath.eig(mpmath.matrix(A.evalf(30).tolist()))[0]]
    return sorted(ev, key=lambda z: (-round(z.real, 9), -round(z.imag, 9)))


def show(name, A):
    print(name)
    for z in eigenvalues(A):
        print(f"  {z.real + 0.0:.17g} {z.imag + 0.0:+.17g}i")


def linearise(L, q, qd, op, q_ind, qd_ind, q_dep=(), qd_dep=(), hol=None, nonhol=None, coords=None):
    lm = me.LagrangesMethod(L, q, hol_coneqs=hol, nonhol_coneqs=nonhol)
    lm.form_lagranges_equations()
    op = {**op, **{c.diff(t, 2): 0 for c in q}}  # a steady point: no accelerations
    if lm.lam_vec.shape[0]:  # the multipliers at the point belong to it (SymPy's linearize docs)
        op = {**op, **lm.solve_multipliers(op_point=op)}
    # Blocks such as [[cos psi, sin psi], [-sin psi, cos psi]] are inverted after trigsimp: SymPy's LU
    # takes sin² + cos² unsimplified for a zero pivot.
    lin = lm.to_linearizer(q_ind=q_ind, qd_ind=qd_ind, q_dep=list(q_dep), qd_dep=list(qd_dep),
                           linear_solver=lambda M, b: sp.trigsimp(M.inv()) * b)
    A, _ = lin.linearize(op_point=op, A_and_B=True)
    return sp.simplify(A)


t = me.dynamicsymbols._t
g_, m_, l_ = 9.81, 1.0, 1.0

# The double pendulum, equal masses and lengths (scenes/double_pendulum.toml), at its four equilibria.
th1, th2 = me.dynamicsymbols('th1 th2')
d1, d2 = me.dynamicsymbols('th1 th2', 1)
T = 2 * l_**2 * d1**2 / 2 + l_**2 * d2**2 / 2 + l_**2 * d1 * d2 * sp.cos(th1 - th2)
V = -2 * g_ * l_ * sp.cos(th1) - g_ * l_ * sp.cos(th2)
for a, b in [(0, 0), (0, sp.pi), (sp.pi, 0), (sp.pi, sp.pi)]:
    A = linearise(T - V, [th1, th2], [d1, d2], {th1: a, th2: b, d1: 0, d2: 0}, [th1, th2], [d1, d2])
    show(f"double_pendulum th1={a} th2={b}", A)

# The pendulum in Cartesian coordinates, the rod a holonomic row (scenes/pendulum_cartesian.toml).
x, y = me.dynamicsymbols('x y')
xd, yd = me.dynamicsymbols('x y', 1)
L = 1.0 * (xd**2 + yd**2) / 2 - 1.0 * 9.81 * y
A = linearise(L, [x, y], [xd, yd], {x: 0, y: -1.2, xd: 0, yd: 0}, [x], [xd], [y], [yd],
              hol=[x**2 + y**2 - 1.2**2])
show("pendulum_cartesian bottom", A)

# The rolling disc (scenes/rolling_disc.toml: m = 1, r = 0.5, g = 9.81) rolling upright at speed v.
X, Y, psi, th, phi = me.dynamicsymbols('x y psi theta phi')
Xd, Yd, psid, thd, phid = me.dynamicsymbols('x y psi theta phi', 1)
m, r, g = 1.0, 0.5, 9.81
S, C = sp.sin, sp.cos
T = m * (2 * phid**2 * r**2 + 4 * phid * psid * r**2 * S(th) + 5 * psid**2 * r**2 * S(th)**2 + psid**2 * r**2
         + 8 * psid * r * Xd * S(th) * C(psi) + 8 * psid * r * Yd * S(psi) * S(th) + 5 * r**2 * thd**2
         + 8 * r * thd * Xd * S(psi) * C(th) - 8 * r * thd * Yd * C(psi) * C(th) + 4 * Xd**2 + 4 * Yd**2) / 8
V = m * g * r * C(th)
rows = [Xd * C(psi) + Yd * S(psi) - r * phid, -Xd * S(psi) + Yd * C(psi)]
for v in [0.5, 1.2, 1.5]:
    op = {X: 0, Y: 0, psi: 0, th: 0, phi: 0, Xd: v, Yd: 0, psid: 0, thd: 0, phid: v / r}
    # The dependent speeds last: SymPy 1.14's permutation_matrix misplaces them otherwise (its P_ud
    # picked y_dot, psi_dot for x_dot, y_dot), which made the block to invert singular.
    A = linearise(T - V, [psi, th, phi, X, Y], [psid, thd, phid, Xd, Yd], op, [psi, th, phi, X, Y],
                  [psid, thd, phid], [], [Xd, Yd], nonhol=rows)
    show(f"rolling_disc v={v}", A)
