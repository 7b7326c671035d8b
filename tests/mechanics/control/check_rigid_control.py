#!/usr/bin/env python3
"""Checks `eomc control scenes/middle_axis_hold.toml` in text and JSON (run by ctest; Mei §3.2): a
free body I = (2, 3, 5) held on its middle axis by torques about body axes 1 and 3, p = r = 0 with
kappa = 2. By hand from Euler's equations with p_dot = -2p, r_dot = -2r imposed:
M1 = A p_dot - (B - C) q r = -4p + 2qr, M3 = C r_dot - (A - B) p q = -10r + pq, no torque about axis 2,
and A I^-1 D = diag(1/2, 1/5) is regular everywhere. usage: check_rigid_control.py EOMC SCENE"""
import json
import subprocess
import sys

eomc, scene = sys.argv[1], sys.argv[2]
d = json.loads(subprocess.run([eomc, "control", scene, "--format", "json"], check=True, capture_output=True,
                              text=True).stdout)
assert [p["name"] for p in d["programs"]] == ["hold_p", "hold_r"], d["programs"]
for p in d["programs"]:
    assert p["space"] == "phase" and p["control"] == "moment" and p["kappa"] == 2, p
assert d["programs"][0]["D"] == [["1", "0", "0"]], d["programs"][0]["D"]
assert d["determinant"] == "1/10", d["determinant"]
assert d["singular_set"] == [] and d["realisable"] is True, d
point = [(0.3, -1.7, 0.45), (0.01, 1.0, 0.01), (-2.0, 0.5, 3.0)]
for p, q, r in point:
    env = {"p": p, "q": q, "r": r}
    lam_p = eval(d["programs"][0]["lambda"]["lambda_hold_p"].replace("^", "**"), env)
    lam_r = eval(d["programs"][1]["lambda"]["lambda_hold_r"].replace("^", "**"), env)
    assert abs(lam_p - (-4 * p + 2 * q * r)) < 1e-12, lam_p
    assert abs(lam_r - (-10 * r + p * q)) < 1e-12, lam_r
    assert eval(d["Qc"]["q"], env) == 0, d["Qc"]
    assert abs(eval(d["Qc"]["p"].replace("^", "**"), env) - lam_p) < 1e-12, d["Qc"]
text = subprocess.run([eomc, "control", scene], check=True, capture_output=True, text=True).stdout
for needle in ("2 program(s), 2 body-axis torque(s) on Euler's equations in p, q, r", "hold_p (phase space): phi = p = 0", "phi_dot + 2 phi = 0", "lambda_hold_p (moment): [1, 0, 0]",
               "Qc_q = 0", "realisable everywhere", "phi(t) = phi0 exp(-2 t)"):
    assert needle in text, (needle, text)
