#!/usr/bin/env python3
"""Checks `eomc control scenes/pendulum_energy_program.toml --format json` (run by ctest): the
pendulum's energy program with one torque is singular where theta_dot = 0, and its control is
tau = -kappa (H - h)/theta_dot. usage: check_control_json.py EOMC SCENE"""
import json
import subprocess
import sys

out = subprocess.run([sys.argv[1], "control", sys.argv[2], "--format", "json"], check=True, capture_output=True, text=True)
d = json.loads(out.stdout)
p = d["programs"][0]
assert p["space"] == "phase" and p["control"] == "actuated" and p["kappa"] == 1, p
assert d["singular_set"] == ["theta_dot"], d["singular_set"]
assert d["determinant"] == "theta_dot", d["determinant"]
assert d["realisable"] is True and "theta_dot = 0" in d["verdict"], d["verdict"]
# λ at theta = 0, theta_dot = 2, g = 9.81, h = 30: -(2 - 9.81 - 30)/2 = 18.905.
lam = p["lambda"]["lambda_energy"].replace("^", "**")
from math import cos, sin  # noqa: E402  (the expression's functions)
value = eval(lam, {"cos": cos, "sin": sin, "theta": 0.0, "theta_dot": 2.0, "g": 9.81, "h": 30.0})
assert abs(value - 18.905) < 1e-12, value
