#!/usr/bin/env python3
"""Whole `eomc generate` against SymPy at scale, on both scene forms of the n-link planar chain.

For each n in --compare: writes the chain given by bodies and given as one [lagrangian] T
(bench/make_pendulum_scenes.py, --form lagrangian), times the whole `eomc generate` process on
each (median of --repeat runs; also with --jacobian when this eomc has that flag) and SymPy's
KanesMethod derive + cse of the same system (bench/sympy_pendulum.py, one fresh process), and
checks that the two forms' kernels cost the same ("mass_matrix + forcing" row of the banner).
For each n in --scaling: eomc's generate time on both forms, `timing derive` from --timings, and
the exponent p of time ~ n^p fitted by least squares on log-log over those n. Writes
OUT/generator_scaling.csv and OUT/generator_scaling.md and prints the markdown.

usage: run_generator_scaling.py [--compare 16 32] [--scaling 16 24 32 48] [--repeat 3] [-o bench/results]
"""
import argparse
import csv
import json
import math
import os
import pathlib
import re
import shlex
import statistics
import subprocess
import sys
import time

from eomc_bench import find_eomc

BENCH = pathlib.Path(__file__).resolve().parent
ROOT = BENCH.parent
FORMS = ("bodies", "lagrangian")


def scene_path(work, form, n):
    return work / (f"pendulum_{n}.toml" if form == "bodies" else f"pendulum_lagrangian_{n}.toml")


def has_flag(eomc, flag):
    r = subprocess.run([str(eomc), "generate", "--help"], capture_output=True, text=True)
    return flag in r.stdout


def generate(eomc, scene, out_dir, repeat, extra=()):
    """Median wall time of the whole process, and of its derive stage (--timings)."""
    walls, derives = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = subprocess.run([str(eomc), "generate", "--timings", *extra, str(scene), "-o", str(out_dir)],
                           capture_output=True, text=True)
        walls.append(time.perf_counter() - t0)
        if r.returncode != 0:
            sys.exit(f"eomc generate failed on {scene}:\n{r.stderr}")
        m = re.search(r"^timing derive ([0-9.eE+-]+)$", r.stderr, re.M)
        derives.append(float(m.group(1)) if m else float("nan"))
    return statistics.median(walls), statistics.median(derives)


def banner_ops(header):
    m = re.search(r"^//\s+mass_matrix \+ forcing\s+(\d+)\s+->\s+(\d+)", header, re.M)
    return int(m.group(2)) if m else None


def fit_exponent(ns, ts):
    xs = [math.log(n) for n in ns]
    ys = [math.log(t) for t in ts]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--compare", type=int, nargs="+", default=[16, 32])
    ap.add_argument("--scaling", type=int, nargs="+", default=[16, 24, 32, 48])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--eomc")
    ap.add_argument("-o", "--output-dir", type=pathlib.Path, default=BENCH / "results")
    a = ap.parse_args()
    command = "python3 " + " ".join(shlex.quote(x) for x in [os.path.relpath(__file__, ROOT)] + sys.argv[1:])
    eomc = find_eomc(a.eomc)
    out = a.output_dir
    work = out / "work"
    work.mkdir(parents=True, exist_ok=True)
    sizes = sorted(set(a.compare) | set(a.scaling))
    for form in FORMS:
        subprocess.run([sys.executable, str(BENCH / "make_pendulum_scenes.py"), "--form", form, str(work),
                        *map(str, sizes)], check=True)
    jacobian = has_flag(eomc, "--jacobian")
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())

    rows = []
    for n in sizes:
        row = {"n": n}
        for form in FORMS:
            print(f"n = {n}: eomc generate, {form}", file=sys.stderr, flush=True)
            wall, derive = generate(eomc, scene_path(work, form, n), work, a.repeat)
            row[f"{form}_generate_s"], row[f"{form}_derive_s"] = wall, derive
            if jacobian and n in a.compare:
                row[f"{form}_generate_jacobian_s"], _ = generate(eomc, scene_path(work, form, n), work, a.repeat,
                                                                 ("--jacobian",))
            name = f"pendulum_{n}.hpp" if form == "bodies" else f"pendulum_lagrangian_{n}.hpp"
            row[f"{form}_ops"] = banner_ops((work / name).read_text())
        if n in a.compare:
            print(f"n = {n}: sympy kane", file=sys.stderr, flush=True)
            r = subprocess.run([sys.executable, str(BENCH / "sympy_pendulum.py"), str(n), "--method", "kane",
                                "-o", str(work)], capture_output=True, text=True, check=True)
            kane = json.loads(r.stdout)
            row["kane_derive_cse_s"] = kane["derive_s"] + kane["cse_s"]
        rows.append(row)

    fields = sorted({k for r in rows for k in r}, key=lambda k: (k != "n", k))
    with open(out / "generator_scaling.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})

    md = [f"Command: `{command}`", "",
          f"eomc binary {os.path.relpath(eomc, ROOT)}; {os.cpu_count()} CPUs, load average at start {load}; "
          f"whole `eomc generate` process, median of {a.repeat} runs; SymPy KanesMethod derive + cse, one run "
          f"(bench/sympy_pendulum.py). `eomc generate --jacobian`: "
          + ("measured." if jacobian else "this eomc has no such flag (the Jacobian is always generated)."), "",
          "| n | generate, bodies (s) | generate, [lagrangian] (s) | SymPy Kane derive + cse (s) "
          "| SymPy / eomc, bodies | SymPy / eomc, [lagrangian] | derive, bodies (s) | derive, [lagrangian] (s) "
          "| ops M + f, bodies | ops M + f, [lagrangian] |", "|" + "---:|" * 10]
    for r in rows:
        k = r.get("kane_derive_cse_s")
        md.append(f"| {r['n']} | {r['bodies_generate_s']:.3g} | {r['lagrangian_generate_s']:.3g} "
                  f"| {k:.3g} | {k / r['bodies_generate_s']:.1f}× | {k / r['lagrangian_generate_s']:.1f}× "
                  if k else f"| {r['n']} | {r['bodies_generate_s']:.3g} | {r['lagrangian_generate_s']:.3g} | — | — | — ")
        md[-1] += (f"| {r['bodies_derive_s']:.3g} | {r['lagrangian_derive_s']:.3g} "
                   f"| {r['bodies_ops']} | {r['lagrangian_ops']} |")
    sc = [r for r in rows if r["n"] in a.scaling]
    ns = [r["n"] for r in sc]
    md += ["", f"Fitted exponent p of time ~ n^p over n = {', '.join(map(str, ns))}:"]
    for form in FORMS:
        p_gen = fit_exponent(ns, [r[f"{form}_generate_s"] for r in sc])
        p_der = fit_exponent(ns, [r[f"{form}_derive_s"] for r in sc])
        md.append(f"- {form}: whole generate {p_gen:.2f}, derive {p_der:.2f} "
                  f"(target ≤ 3 for generate: {'met' if p_gen <= 3 else 'NOT met'})")
    if jacobian:
        md += ["", "With `--jacobian` (∂ẋ/∂x lowered and emitted too; the SymPy side forms no Jacobian):", "",
               "| n | generate --jacobian, bodies (s) | generate --jacobian, [lagrangian] (s) "
               "| SymPy / eomc, bodies | SymPy / eomc, [lagrangian] |", "|" + "---:|" * 5]
        for r in rows:
            if "kane_derive_cse_s" not in r:
                continue
            k, b, l = r["kane_derive_cse_s"], r["bodies_generate_jacobian_s"], r["lagrangian_generate_jacobian_s"]
            md.append(f"| {r['n']} | {b:.3g} | {l:.3g} | {k / b:.1f}× | {k / l:.1f}× |")
    md += ["", "Targets (≥ 10× faster than SymPy Kane derive + cse, whole generate):"]
    for r in rows:
        if "kane_derive_cse_s" not in r:
            continue
        for form in FORMS:
            ratio = r["kane_derive_cse_s"] / r[f"{form}_generate_s"]
            md.append(f"- n = {r['n']}, {form}: {ratio:.1f}× ({'met' if ratio >= 10 else 'NOT met'}; "
                      f"against eomc's derive stage alone {r['kane_derive_cse_s'] / r[f'{form}_derive_s']:.0f}×)")
    same = all(r["bodies_ops"] and r["lagrangian_ops"] and abs(r["lagrangian_ops"] - r["bodies_ops"]) <= 0.1 * r["bodies_ops"]
               for r in rows)
    md.append(f"- [lagrangian] kernel's operations within 10 % of the bodies' at every n: {'met' if same else 'NOT met'}")
    (out / "generator_scaling.md").write_text("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
