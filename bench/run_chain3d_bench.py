#!/usr/bin/env python3
"""End to end on the n-link 3-D pendulum chain: eomc generate + compile against SymPy's
KanesMethod + cse + ccode + compile (issue 19), then the two kernels' agreement and rhs cost.

The chain is bench/make_pendulum_scenes.py --form spatial (2n coordinates); the SymPy side is
bench/sympy_pendulum.py --spatial, the same positions, masses and gravity. Each side's cost is
the CPU time (user + system, from the children's rusage) of:
  - eomc: the whole `eomc generate` process, then g++ on bench/compile_probe.cpp, the
    translation unit a user's program needs to call rhs() (and jacobian() for the --jacobian
    run, whose header carries it);
  - SymPy: the whole sympy_pendulum.py process (import, Kane, cse, ccode, writing the header),
    then g++ on bench/compile_probe.cpp with its M, f and an Eigen PartialPivLU solve for q̈.
Median of --repeat rounds, the sides alternating within a round. Then bench/rhs_timing.cpp
checks M, f and q̈ agree at 256 random states (angles in ±1.2, clear of cos b_k = 0 where M is
singular) and times rhs per call. Writes OUT/chain3d.csv and OUT/chain3d.md, prints the markdown.

usage: run_chain3d_bench.py [--links 12] [--repeat 3] [--eomc PATH] [-o bench/results]
"""
import argparse
import csv
import json
import os
import pathlib
import resource
import shlex
import statistics
import subprocess
import sys

from eomc_bench import find_eomc

BENCH = pathlib.Path(__file__).resolve().parent
ROOT = BENCH.parent
CXXFLAGS = ["-O2", "-std=c++20"]
INCLUDES = [f"-I{ROOT / 'runtime' / 'include'}", "-I/usr/include/eigen3"]


def cpu_of(cmd, **kw):
    """CPU seconds (user + system) of a child process and all it waited for; its stdout."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"failed: {shlex.join(map(str, cmd))}\n{r.stderr}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), r.stdout


def model_name(scene_name):
    return "".join(part[:1].upper() + part[1:] for part in scene_name.split("_"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--links", type=int, default=12)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--eomc")
    ap.add_argument("-o", "--output-dir", type=pathlib.Path, default=BENCH / "results")
    a = ap.parse_args()
    command = "python3 " + " ".join(shlex.quote(x) for x in [os.path.relpath(__file__, ROOT)] + sys.argv[1:])
    eomc = find_eomc(a.eomc)
    n = a.links
    nq = 2 * n
    work = a.output_dir / "work"
    work.mkdir(parents=True, exist_ok=True)
    subprocess.run([sys.executable, str(BENCH / "make_pendulum_scenes.py"), "--form", "spatial", str(work), str(n)],
                   check=True)
    scene = work / f"chain3d_{n}.toml"
    model = model_name(f"chain3d_{n}")
    jac_dir = work / "jacobian"
    jac_dir.mkdir(exist_ok=True)
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())

    def probe(header_dir, defines):
        return cpu_of(["g++", *CXXFLAGS, *INCLUDES, f"-I{header_dir}", *defines, "-c",
                       str(BENCH / "compile_probe.cpp"), "-o", os.devnull])[0]

    eomc_defines = [f'-DEOMC_HEADER="chain3d_{n}.hpp"', f"-DEOMC_MODEL={model}"]
    runs = {k: [] for k in ("eomc_generate", "eomc_compile", "eomc_jac_generate", "eomc_jac_compile",
                            "sympy_generate", "sympy_compile")}
    sympy_stages = []
    for _ in range(a.repeat):
        runs["eomc_generate"].append(cpu_of([str(eomc), "generate", str(scene), "-o", str(work)])[0])
        runs["eomc_compile"].append(probe(work, eomc_defines))
        runs["eomc_jac_generate"].append(cpu_of([str(eomc), "generate", "--jacobian", str(scene), "-o", str(jac_dir)])[0])
        runs["eomc_jac_compile"].append(probe(jac_dir, eomc_defines + ["-DPROBE_JACOBIAN"]))
        t, out = cpu_of([sys.executable, str(BENCH / "sympy_pendulum.py"), str(n), "--spatial", "--method", "kane",
                         "-o", str(work)])
        runs["sympy_generate"].append(t)
        sympy_stages.append(json.loads(out))
        runs["sympy_compile"].append(probe(work, [f'-DSYMPY_HEADER="sympy_mass_forcing_{n}.hpp"', f"-DSYMPY_N={nq}"]))
    med = {k: statistics.median(v) for k, v in runs.items()}
    kane = sympy_stages[-1]

    exe = work / f"rhs_timing_chain3d_{n}"
    subprocess.run(["g++", *CXXFLAGS, *INCLUDES, f"-I{work}", *eomc_defines,
                    f'-DSYMPY_HEADER="sympy_mass_forcing_{n}.hpp"', "-DANGLE_RANGE=1.2",
                    str(BENCH / "rhs_timing.cpp"), "-o", str(exe)], check=True)
    rt = dict(line.split() for line in subprocess.run([str(exe)], capture_output=True, text=True,
                                                       check=True).stdout.splitlines())
    header = (work / f"chain3d_{n}.hpp").read_text()
    ops = next((line.split("->")[1].split()[0] for line in header.splitlines()
                if line.startswith("//   mass_matrix + forcing")), "?")

    row = {"links": n, "coordinates": nq, **{f"{k}_cpu_s": v for k, v in med.items()},
           "sympy_derive_s": statistics.median(s["derive_s"] for s in sympy_stages),
           "sympy_cse_s": statistics.median(s["cse_s"] for s in sympy_stages),
           "ops_eomc": ops, "ops_sympy": kane["ops_after"],
           "rhs_eomc_ns": float(rt["eomc_rhs_ns"]), "rhs_sympy_ns": float(rt["sympy_rhs_ns"]),
           "rhs_paired_ratio": float(rt["paired_ratio"]), "rel_diff_M": float(rt["rel_diff_M"]),
           "rel_diff_f": float(rt["rel_diff_f"]), "rel_diff_qdd": float(rt["rel_diff_qdd"])}
    a.output_dir.mkdir(parents=True, exist_ok=True)
    with open(a.output_dir / "chain3d.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(row))
        w.writeheader()
        w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})

    eomc_total = med["eomc_generate"] + med["eomc_compile"]
    jac_total = med["eomc_jac_generate"] + med["eomc_jac_compile"]
    sympy_total = med["sympy_generate"] + med["sympy_compile"]
    md = [f"Command: `{command}`", "",
          f"eomc binary {os.path.relpath(eomc, ROOT)}; {os.cpu_count()} CPUs, load average at start {load}; "
          f"CPU seconds, median of {a.repeat} rounds; g++ {' '.join(CXXFLAGS)} on bench/compile_probe.cpp.", "",
          f"| {n}-link 3-D chain ({nq} coordinates) | generate (CPU s) | compile (CPU s) | generate + compile (CPU s) |",
          "|---|---:|---:|---:|",
          f"| eomc generate | {med['eomc_generate']:.3g} | {med['eomc_compile']:.3g} | {eomc_total:.3g} |",
          f"| eomc generate --jacobian (rhs and jacobian compiled) | {med['eomc_jac_generate']:.3g} "
          f"| {med['eomc_jac_compile']:.3g} | {jac_total:.3g} |",
          f"| SymPy Kane + cse + ccode (whole process; derive {row['sympy_derive_s']:.3g} s, cse "
          f"{row['sympy_cse_s']:.3g} s) + PartialPivLU | {med['sympy_generate']:.3g} | {med['sympy_compile']:.3g} "
          f"| {sympy_total:.3g} |", "",
          f"- SymPy / eomc, generate + compile of the same outputs (M, f, q̈): {sympy_total / eomc_total:.1f}× — "
          f"target: eomc faster ({'met' if eomc_total < sympy_total else 'NOT met'})",
          f"- with eomc's Jacobian ∂ẋ/∂x as well, which the SymPy side does not produce: "
          f"{sympy_total / jac_total:.2f}× (the Jacobian's compile is {med['eomc_jac_compile'] - med['eomc_compile']:.3g} s "
          f"of it)",
          f"- operations in M + f after CSE: eomc {ops}, SymPy {kane['ops_after']}",
          f"- rhs per call: eomc {row['rhs_eomc_ns']:.0f} ns, SymPy + PartialPivLU {row['rhs_sympy_ns']:.0f} ns, "
          f"paired SymPy / eomc {row['rhs_paired_ratio']:.2f}×",
          f"- agreement at 256 states: M {row['rel_diff_M']:.1e}, f {row['rel_diff_f']:.1e}, "
          f"q̈ {row['rel_diff_qdd']:.1e} (normwise relative)"]
    (a.output_dir / "chain3d.md").write_text("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
