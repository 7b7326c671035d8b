#!/usr/bin/env python3
"""What the stricter event locator costs (issue 28): two eomc builds side by side on the bundled
contact scenes and the scenes with [events]: steps, rhs evaluations, impacts (or events) and the
least integration time (the summary's wall_s) of --repeat runs each, the two builds interleaved.

    bench/run_locator_cost.py OLD_EOMC NEW_EOMC [--repeat 7]

OLD_EOMC: an eomc built from the commit before the change (git worktree add, cmake, build)."""
import argparse
import glob
import json
import os
import subprocess
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
scenes_dir = os.path.join(here, "..", "scenes")


def scenes():
    out = []
    for path in sorted(glob.glob(os.path.join(scenes_dir, "*.toml"))):
        text = open(path).read()
        if "[[unilateral]]" in text or "[events]" in text:
            out.append(path)
    return out


def run(eomc, scene, cache):
    r = subprocess.run([eomc, "simulate", scene, "--summary", "json", "--cache-dir", cache],
                       capture_output=True, text=True, check=True)
    d = json.loads(r.stdout)
    found = len(d["contacts"]["impacts"]) if "contacts" in d else len(d.get("events", []))
    return d["steps"], d["rhs_evals"], found, d["wall_s"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--repeat", type=int, default=7)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        print(f"{'scene':24s} {'steps':>15s} {'rhs':>17s} {'impacts/events':>15s} {'wall (ms)':>21s}")
        for scene in scenes():
            best = {}
            for _ in range(a.repeat):  # interleaved: each pair of runs sees the same machine
                for label, eomc in (("old", a.old), ("new", a.new)):
                    s = run(eomc, scene, os.path.join(tmp, label))
                    prev = best.get(label)
                    best[label] = s if prev is None or s[3] < prev[3] else prev
            o, n = best["old"], best["new"]
            print(f"{os.path.basename(scene)[:-5]:24s} {o[0]:6d} -> {n[0]:6d} {o[1]:7d} -> {n[1]:7d} "
                  f"{o[2]:5d} -> {n[2]:5d} {o[3] * 1e3:8.3f} -> {n[3] * 1e3:8.3f} ({n[3] / o[3]:.2f}x)")


if __name__ == "__main__":
    main()
