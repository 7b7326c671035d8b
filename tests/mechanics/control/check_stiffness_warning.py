#!/usr/bin/env python3
"""Checks the stiffness warning of `eomc simulate` (run by ctest): a particle held on a circle by
Galiullin's law with alpha = beta = 200 (a double eigenvalue -200 of the residual dynamics) under
rk4 at step 0.02, h lambda = -4, outside RK4's stability interval (-2.785, 0]: the warning names the
program and its gains on stderr, and the run is still made (exit 0, a summary on stdout). At step
0.001 (h lambda = -0.2) there is no warning. usage: check_stiffness_warning.py EOMC WORKDIR"""
import os
import subprocess
import sys

eomc, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
scene = os.path.join(work, "stiff_circle.toml")
with open(scene, "w") as f:
    f.write("""[scene]
name = "stiff_circle"
[coordinates]
x = { initial = 1.0, rate = 0.0 }
y = { initial = 0.0, rate = 1.0 }
[lagrangian]
T = "(x_dot^2 + y_dot^2)/2"
V = "0"
[[program]]
name = "hoop"
constraint = "x^2 + y^2 - 1"
erugin = { alpha = 200, beta = 200 }
""")


def simulate(step):
    return subprocess.run([eomc, "simulate", scene, "--integrator", "rk4", "--step", step, "--t-end", "0.1"],
                          capture_output=True, text=True, cwd=work,
                          env=dict(os.environ, XDG_CACHE_HOME=os.path.join(work, "cache")))


stiff = simulate("0.02")
assert stiff.returncode == 0, stiff.stderr
warning = [line for line in stiff.stderr.splitlines() if "warning" in line]
assert len(warning) == 1, stiff.stderr
assert "'hoop' with alpha = 200, beta = 200" in warning[0], warning[0]
assert "stiff for rk4 at step 0.02" in warning[0] and "h lambda = -4" in warning[0], warning[0]
assert "step below 0.0139" in warning[0], warning[0]  # 2.785/200
assert "hoop" in stiff.stdout, stiff.stdout  # the run was made: its program report
calm = simulate("0.001")
assert calm.returncode == 0, calm.stderr
assert "warning" not in calm.stderr, calm.stderr
print(warning[0])
