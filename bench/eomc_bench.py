"""What the bench drivers share: where the eomc binary is.

Imported by the scripts beside it (`python3 bench/<script>.py` puts bench/ on the path).
"""
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent


def find_eomc(explicit=None):
    """--eomc PATH when given; else the first build of this tree that has one (build/ is what
    scripts/setup.sh makes)."""
    if explicit:
        return pathlib.Path(explicit)
    for build in ("build", "build-lead", "build-bench", "build-h"):
        p = ROOT / build / "generator" / "eomc"
        if p.exists():
            return p
    sys.exit("eomc not found: build it (scripts/setup.sh) or pass --eomc")
