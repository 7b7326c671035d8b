#!/usr/bin/env python3
"""eomc against SymPy on the n-link planar pendulum, side by side in one run.

For each n: writes the scene (bench/make_pendulum_scenes.py); runs `eomc generate --timings`
(median of --repeat runs) and reads the operation counts from the header's banner; derives
the same system with SymPy's KanesMethod and LagrangesMethod (bench/sympy_pendulum.py, one
fresh process per method so that neither inherits the other's SymPy cache) and cse's M, f;
compiles bench/rhs_timing.cpp against both kernels with the same flags, which checks that
M, f and q'' agree and times rhs per call. Writes OUT/pendulum.csv and OUT/pendulum.md
(machine, command, table, targets at the largest n) and prints the markdown.

usage: run_pendulum_bench.py [--sizes 2 4 8 12 16] [--skip-lagrange-above N] [-o bench/results]
"""
import argparse
import csv
import json
import os
import pathlib
import platform
import re
import shlex
import statistics
import subprocess
import sys
import time

from eomc_bench import find_eomc

BENCH = pathlib.Path(__file__).resolve().parent
ROOT = BENCH.parent
CXXFLAGS = ["-O2", "-std=c++20"]


def eomc_banner_ops(header_text, n):
    """(ops as derived, ops after CSE) of what rhs evaluates, from the banner: the joint
    `mass_matrix + forcing` row, or for n <= 2 (no joint block: q'' is closed form) the sum
    of the separate mass_matrix and forcing rows."""
    def row(label):
        m = re.search(rf"^//\s+{re.escape(label)}\s+(\d+)\s+->\s+(\d+)", header_text, re.M)
        return (int(m.group(1)), int(m.group(2))) if m else None
    joint = row("mass_matrix + forcing")
    if joint:
        return joint
    mm, ff = row("mass_matrix"), row("forcing")
    return mm[0] + ff[0], mm[1] + ff[1]


def run_eomc(eomc, scene, out_dir, repeat):
    """Stage times (median over runs) from `--timings`; without that flag (older eomc), the
    whole process's wall time stands for every stage it would have covered."""
    runs = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = subprocess.run([str(eomc), "generate", "--timings", str(scene), "-o", str(out_dir)],
                           capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if r.returncode != 0 and "--timings" in r.stderr:
            r = subprocess.run([str(eomc), "generate", str(scene), "-o", str(out_dir)],
                               capture_output=True, text=True, check=True)
            wall = time.perf_counter() - t0
        elif r.returncode != 0:
            sys.exit(f"eomc generate failed on {scene}:\n{r.stderr}")
        stages = {m.group(1): float(m.group(2))
                  for m in re.finditer(r"^timing (\S+) ([0-9.eE+-]+)$", r.stderr, re.M)}
        stages["process"] = wall
        if "derive" in stages:
            stages["derive_cse"] = stages.get("parse", 0) + stages["derive"] + stages["cse_mass_forcing"]
        else:
            stages["derive_cse"] = wall   # no --timings: an upper bound
        runs.append(stages)
    med = {k: statistics.median(r[k] for r in runs) for k in runs[0]}
    med["timings_flag"] = "derive" in runs[0]
    return med


def run_sympy(n, method, out_dir, timeout):
    cmd = [sys.executable, str(BENCH / "sympy_pendulum.py"), str(n), "--method", method, "-o", str(out_dir)]
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=True)
    except subprocess.TimeoutExpired:
        return None
    return json.loads(r.stdout)


def run_rhs_timing(n, model, work, sympy_kane, sympy_lagrange):
    exe = work / f"rhs_timing_{n}"
    cmd = ["g++", *CXXFLAGS, f"-I{ROOT / 'runtime' / 'include'}", "-I/usr/include/eigen3", f"-I{work}",
           f'-DEOMC_HEADER="pendulum_{n}.hpp"', f"-DEOMC_MODEL={model}",
           f'-DSYMPY_HEADER="{pathlib.Path(sympy_kane["header"]).name}"']
    if sympy_lagrange:
        cmd.append(f'-DSYMPY_LAGRANGE_HEADER="{pathlib.Path(sympy_lagrange["header"]).name}"')
    cmd += [str(BENCH / "rhs_timing.cpp"), "-o", str(exe)]
    subprocess.run(cmd, check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    return {k: float(v) for k, v in (line.split() for line in out.splitlines())}


def machine():
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    gxx = subprocess.run(["g++", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    import sympy
    return {"nproc": os.cpu_count(), "cpu": cpu, "g++": gxx, "sympy": sympy.__version__,
            "python": platform.python_version(), "load average at start": " ".join(f"{x:.2f}" for x in os.getloadavg())}


def fmt(x, digits=3):
    if x is None or x == "":
        return "—"
    if isinstance(x, float):
        return f"{x:.{digits}g}"
    return str(x)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[2, 4, 8, 12, 16])
    ap.add_argument("--skip-lagrange-above", type=int, default=None, metavar="N",
                    help="run LagrangesMethod only for n <= N (it takes about a minute at n = 16)")
    ap.add_argument("--lagrange-timeout", type=float, default=600, help="seconds per size before giving up")
    ap.add_argument("--repeat", type=int, default=5, help="eomc generate runs per size (median)")
    ap.add_argument("--eomc", help="eomc binary (default: build/generator/eomc, as scripts/setup.sh builds it)")
    ap.add_argument("-o", "--output-dir", type=pathlib.Path, default=BENCH / "results")
    a = ap.parse_args()

    command = "python3 " + " ".join(shlex.quote(x) for x in
                                    [os.path.relpath(__file__, ROOT)] + sys.argv[1:])
    eomc = find_eomc(a.eomc)
    out = a.output_dir
    work = out / "work"   # generated scenes and headers: reproducible, not committed
    work.mkdir(parents=True, exist_ok=True)
    info = machine()
    subprocess.run([sys.executable, str(BENCH / "make_pendulum_scenes.py"), str(work),
                    *map(str, a.sizes)], check=True)

    rows = []
    for n in a.sizes:
        print(f"n = {n}: eomc", file=sys.stderr, flush=True)
        e = run_eomc(eomc, work / f"pendulum_{n}.toml", work, a.repeat)
        header = (work / f"pendulum_{n}.hpp").read_text()
        e_before, e_after = eomc_banner_ops(header, n)
        model = re.search(r"^using (\w+) = Basic\w+<double>;", header, re.M).group(1)

        print(f"n = {n}: sympy kane", file=sys.stderr, flush=True)
        kane = run_sympy(n, "kane", work, None)
        lag = None
        lag_note = ""
        if a.skip_lagrange_above is not None and n > a.skip_lagrange_above:
            lag_note = "skipped"
        else:
            print(f"n = {n}: sympy lagrange", file=sys.stderr, flush=True)
            lag = run_sympy(n, "lagrange", work, a.lagrange_timeout)
            if lag is None:
                lag_note = f"timeout {a.lagrange_timeout:.0f} s"

        print(f"n = {n}: rhs timing", file=sys.stderr, flush=True)
        rt = run_rhs_timing(n, model, work, kane, lag)
        # Same system, same conventions: anything beyond rounding is a bug, not a result.
        for key in ("rel_diff_M", "rel_diff_f", "rel_diff_lagrange_M", "rel_diff_lagrange_f"):
            if rt.get(key, 0) > 1e-12:
                sys.exit(f"n = {n}: {key} = {rt[key]:.3e}: SymPy and eomc disagree")
        if rt["rel_diff_qdd"] > 1e-10:
            sys.exit(f"n = {n}: q'' differs by {rt['rel_diff_qdd']:.3e}")

        eomc_s = e["derive_cse"]
        kane_s = kane["derive_s"] + kane["cse_s"]
        lag_s = lag["derive_s"] + lag["cse_s"] if lag else None
        rows.append({
            "n": n,
            "eomc_derive_cse_s": eomc_s,
            "eomc_parse_s": e.get("parse", ""), "eomc_derive_s": e.get("derive", ""),
            "eomc_cse_mass_forcing_s": e.get("cse_mass_forcing", ""),
            "eomc_generate_process_s": e["process"],
            "kane_derive_s": kane["derive_s"], "kane_cse_s": kane["cse_s"],
            "lagrange_derive_s": lag["derive_s"] if lag else lag_note,
            "lagrange_cse_s": lag["cse_s"] if lag else lag_note,
            "ratio_kane": kane_s / eomc_s,
            "ratio_lagrange": lag_s / eomc_s if lag else "",
            "ratio_kane_derive_only": kane["derive_s"] / eomc_s,
            "ops_eomc_before": e_before, "ops_eomc": e_after,
            "ops_kane_before": kane["ops_before"], "ops_kane_cse": kane["ops_after"],
            "ops_lagrange_cse": lag["ops_after"] if lag else "",
            "rhs_eomc_ns": rt["eomc_rhs_ns"], "rhs_sympy_ns": rt["sympy_rhs_ns"],
            "rhs_ratio": rt["paired_ratio"],   # median over paired samples of SymPy / eomc
            "rhs_eomc_min_ns": rt["eomc_rhs_min_ns"], "rhs_sympy_min_ns": rt["sympy_rhs_min_ns"],
            "rel_diff_M": rt["rel_diff_M"], "rel_diff_f": rt["rel_diff_f"], "rel_diff_qdd": rt["rel_diff_qdd"],
            "rel_diff_lagrange_M": rt.get("rel_diff_lagrange_M", ""),
            "rel_diff_lagrange_f": rt.get("rel_diff_lagrange_f", ""),
            "eomc_timings_flag": e["timings_flag"],
        })

    with open(out / "pendulum.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})

    md = [f"Command: `{command}`", "",
          "Machine: " + "; ".join(f"{k} {v}" for k, v in info.items())
          + f"; eomc binary {os.path.relpath(eomc, ROOT)}; both kernels compiled with `g++ {' '.join(CXXFLAGS)}`.", "",
          "| n | eomc derive+CSE (s) | SymPy Kane derive + cse (s) | SymPy Lagrange derive + cse (s) "
          "| Kane / eomc | Lagrange / eomc | ops eomc | ops SymPy Kane cse | ops SymPy Lagrange cse "
          "| rhs eomc, median (min) ns | rhs SymPy+LU, median (min) ns | SymPy / eomc rhs (paired median) | max rel. diff q'' |",
          "|" + "---:|" * 13]
    for r in rows:
        lag = (f"{r['lagrange_derive_s']:.3g} + {r['lagrange_cse_s']:.3g}"
               if isinstance(r["lagrange_derive_s"], float) else r["lagrange_derive_s"] or "—")
        md.append(f"| {r['n']} | {r['eomc_derive_cse_s']:.3g} | {r['kane_derive_s']:.3g} + {r['kane_cse_s']:.3g} "
                  f"| {lag} | {r['ratio_kane']:.1f}× | {fmt(r['ratio_lagrange'], 3)}{'×' if r['ratio_lagrange'] else ''} "
                  f"| {r['ops_eomc']} | {r['ops_kane_cse']} | {fmt(r['ops_lagrange_cse'])} "
                  f"| {r['rhs_eomc_ns']:.0f} ({r['rhs_eomc_min_ns']:.0f}) | {r['rhs_sympy_ns']:.0f} ({r['rhs_sympy_min_ns']:.0f}) "
                  f"| {r['rhs_ratio']:.2f}× | {r['rel_diff_qdd']:.1e} |")

    big = rows[-1]
    sympy_best = min(x for x in [big["kane_derive_s"] + big["kane_cse_s"],
                                 big["lagrange_derive_s"] + big["lagrange_cse_s"]
                                 if isinstance(big["lagrange_derive_s"], float) else None] if x is not None)
    ops_sympy = min(x for x in [big["ops_kane_cse"], big["ops_lagrange_cse"] or None] if x is not None)
    md += ["", f"Targets at n = {big['n']}:",
           f"- derive + CSE ≥ 10× faster than SymPy's faster method: {sympy_best / big['eomc_derive_cse_s']:.1f}× "
           f"({'met' if sympy_best / big['eomc_derive_cse_s'] >= 10 else 'NOT met'}; "
           f"against Kane's derivation alone, without its cse: {big['ratio_kane_derive_only']:.1f}×)"]
    if big["ratio_lagrange"]:
        md.append(f"- ≥ 30× faster than LagrangesMethod: {big['ratio_lagrange']:.1f}× "
                  f"({'met' if big['ratio_lagrange'] >= 30 else 'NOT met'})")
    else:
        md.append("- ≥ 30× faster than LagrangesMethod: not measured (Lagrange skipped)")
    md += [f"- ops after CSE ≤ sympy.cse's: {big['ops_eomc']} vs {ops_sympy} "
           f"({'met' if big['ops_eomc'] <= ops_sympy else 'NOT met'}, ratio {big['ops_eomc'] / ops_sympy:.2f}; "
           f"SymPy Kane {big['ops_kane_cse']}, Lagrange {fmt(big['ops_lagrange_cse'])})",
           f"- rhs no slower than SymPy ccode + LU: {big['rhs_eomc_ns']:.0f} ns vs {big['rhs_sympy_ns']:.0f} ns median, "
           f"{big['rhs_eomc_min_ns']:.0f} vs {big['rhs_sympy_min_ns']:.0f} ns minimum; paired SymPy/eomc {big['rhs_ratio']:.2f}× "
           f"({'met' if big['rhs_ratio'] >= 1 else 'NOT met'})"]
    (out / "pendulum.md").write_text("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
