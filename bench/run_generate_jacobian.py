#!/usr/bin/env python3
"""`eomc generate` on the n-link planar chain: an eomc from before issue 19's Jacobian work (which
always builds ∂ẋ/∂x, entry by entry) against the current one without and with --jacobian.

For each n the three runs alternate, `--repeats` times; each run is one fresh process, its CPU
time (user + system, from wait4) and its `--timings` stages are recorded, and the median is
reported. The `--timings` stages are wall-clock times, which a loaded machine inflates; the cost
of the Jacobian is therefore given as CPU time, the median CPU of a run with it minus that of the
current eomc without it (derive, CSE of M and f and the rest are the same code in all three). The
exponent p of time ≈ c·n^p is a least-squares fit of log time against log n over the sizes ≥ 16.

usage: run_generate_jacobian.py --before OLD_EOMC --after NEW_EOMC [--sizes 8 16 32 48]
                                [--repeats 3] [-o bench/results]
       run_generate_jacobian.py --from-csv bench/results/generate_jacobian.csv [-o bench/results]
       (the table again from a run's CSV)
"""
import argparse
import csv
import math
import os
import pathlib
import platform
import statistics
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent


def run(eomc, scene, out_dir, extra):
    """One `eomc generate --timings` process: (cpu seconds, {stage: seconds}, header bytes)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    proc = subprocess.Popen([eomc, "generate", str(scene), "-o", str(out_dir), "--timings", *extra],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    stderr = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    if status != 0:
        sys.exit(f"{eomc} generate {scene} failed:\n{stderr}")
    stages = {}
    for line in stderr.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[0] == "timing":
            stages[parts[1]] = float(parts[2])
    header = out_dir / (scene.stem + ".hpp")  # the scene's name is its file's
    return usage.ru_utime + usage.ru_stime, stages, header.stat().st_size


def fit_exponent(ns, ts):
    xs, ys = [math.log(n) for n in ns], [math.log(t) for t in ts]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--before")
    ap.add_argument("--after")
    ap.add_argument("--from-csv")
    ap.add_argument("--sizes", type=int, nargs="+", default=[8, 16, 32, 48])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("-o", "--output", default=str(HERE / "results"))
    a = ap.parse_args()
    out = pathlib.Path(a.output)
    if a.from_csv:
        with open(a.from_csv) as f:
            rows = [{k: (int(v) if k == "n" else float(v)) for k, v in r.items()} for r in csv.DictReader(f)]
        return report(rows, out, None)
    if not (a.before and a.after):
        ap.error("--before and --after are required (or --from-csv)")
    work = out / "work" / "generate_jacobian"
    scenes = work / "scenes"
    subprocess.run([sys.executable, str(HERE / "make_pendulum_scenes.py"), str(scenes), *map(str, a.sizes)],
                   check=True, stdout=subprocess.DEVNULL)
    configs = [("before", a.before, []), ("after", a.after, []), ("after_jacobian", a.after, ["--jacobian"])]
    rows = []
    for n in a.sizes:
        scene = scenes / f"pendulum_{n}.toml"
        samples = {name: [] for name, _, _ in configs}
        for _ in range(a.repeats):
            for name, eomc, extra in configs:
                samples[name].append(run(eomc, scene, work / name, extra))
        row = {"n": n}
        for name, _, _ in configs:
            row[f"{name}_cpu_s"] = statistics.median(s[0] for s in samples[name])
            row[f"{name}_jacobian_s"] = statistics.median(s[1].get("jacobian", 0.0) for s in samples[name])
            row[f"{name}_derive_s"] = statistics.median(s[1].get("derive", 0.0) for s in samples[name])
            row[f"{name}_header_bytes"] = samples[name][0][2]
        rows.append(row)
        print(f"n = {n}: " + ", ".join(f"{k} {v:.3g}" for k, v in row.items() if k != "n"), flush=True)

    with open(out / "generate_jacobian.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    report(rows, out, a.repeats)


def report(rows, out, repeats):
    for r in rows:  # the Jacobian's CPU: a run with it minus the current eomc's run without it
        r["before_extra"] = r["before_cpu_s"] - r["after_cpu_s"]
        r["now_extra"] = r["after_jacobian_cpu_s"] - r["after_cpu_s"]
    big = [r for r in rows if r["n"] >= 16]
    lines = [f"Machine: nproc {os.cpu_count()}; {platform.machine()}; load average at end "
             f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}"
             + (f"; {repeats} runs per cell, medians." if repeats else "."), "",
             "| n | before: generate CPU s | now: generate CPU s | now --jacobian: CPU s | Jacobian CPU s: "
             "before, now | before / now | `timing jacobian` (wall) s: before, now | header KiB: before, now, "
             "now --jacobian |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        ratio = r["before_extra"] / r["now_extra"] if r["now_extra"] > 0 else float("nan")
        lines.append(f"| {r['n']} | {r['before_cpu_s']:.3g} | {r['after_cpu_s']:.3g} | {r['after_jacobian_cpu_s']:.3g} | "
                     f"{r['before_extra']:.3g}, {r['now_extra']:.3g} | {ratio:.2f}× | "
                     f"{r['before_jacobian_s']:.3g}, {r['after_jacobian_jacobian_s']:.3g} | "
                     f"{r['before_header_bytes'] / 1024:.0f}, {r['after_header_bytes'] / 1024:.0f}, "
                     f"{r['after_jacobian_header_bytes'] / 1024:.0f} |")
    if len(big) >= 2 and all(r["before_extra"] > 0 and r["now_extra"] > 0 for r in big):
        ns = [r["n"] for r in big]
        lines += ["", f"Exponents over n = {ns[0]}–{ns[-1]} (least squares of log time on log n): the Jacobian's CPU "
                  f"before {fit_exponent(ns, [r['before_extra'] for r in big]):.2f}, now "
                  f"{fit_exponent(ns, [r['now_extra'] for r in big]):.2f}; whole generate before "
                  f"{fit_exponent(ns, [r['before_cpu_s'] for r in big]):.2f}, now without --jacobian "
                  f"{fit_exponent(ns, [r['after_cpu_s'] for r in big]):.2f}, with "
                  f"{fit_exponent(ns, [r['after_jacobian_cpu_s'] for r in big]):.2f}."]
    out.mkdir(parents=True, exist_ok=True)
    (out / "generate_jacobian.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
