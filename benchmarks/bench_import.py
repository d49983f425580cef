"""Start-up cost of the command line against a bare interpreter.

Anchor: ``python -c pass`` (the interpreter and ``site``). Project, each in a
fresh process: ``import attneave``, ``import attneave.stimuli``, ``import
attneave.analysis``, ``attneave --help``,
and ``attneave surprisal`` on a 200-point contour (the whole call: import,
read, compute, write). For every case the script prints the median wall time
of repeated runs and the median import time beyond the anchor's, read from
``python -X importtime`` (the sum of top-level cumulative times), which is
less sensitive to machine load than wall time.

Target (issue 13): ``attneave --help`` and a ``surprisal`` call in well under
0.3 s of import time.
Issue 24: as fast after the move into one ``attneave`` namespace as before;
``--root`` measures an older checkout (one from before the move, with its
``stimuli`` and ``analysis`` top-level packages, is measured under its own
names) in the same run.
Usage: python benchmarks/bench_import.py [--repeats 7] [--root OTHER_CHECKOUT]
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

from _machine import header


def import_us(stderr):
    """Total import time (us) from -X importtime output: the sum of top-level entries."""
    total = 0
    for line in stderr.splitlines():
        if not line.startswith("import time:") or "cumulative" in line:
            continue
        _, cum_us, name = line[len("import time:"):].split("|", 2)
        if len(name) - len(name.lstrip(" ")) == 1:  # top level; deeper ones are inside it
            total += int(cum_us)
    return total


def run(argv, repeats, env=None):
    walls, imports = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        p = subprocess.run([sys.executable, "-X", "importtime", *argv], capture_output=True, text=True, env=env)
        walls.append(time.perf_counter() - t0)
        if p.returncode != 0:
            raise SystemExit(f"{argv}: exit {p.returncode}: {p.stderr[-500:]}")
        imports.append(import_us(p.stderr))
    return statistics.median(walls), statistics.median(imports) / 1e6


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--root", help="measure another checkout of attneave (e.g. an older commit) instead")
    args = ap.parse_args()
    env = None
    if args.root:
        env = dict(os.environ, PYTHONPATH=os.path.abspath(args.root))
    header("start-up: attneave commands against python -c pass", packages=("numpy", "scipy"))
    with tempfile.TemporaryDirectory() as d:
        th = 2 * np.pi * np.arange(200) / 200
        src = os.path.join(d, "c.csv")
        np.savetxt(src, np.c_[100 + 50 * np.cos(th), 100 + 30 * np.sin(th)], delimiter=",",
                   header="x,y", comments="")
        legacy = bool(args.root) and os.path.exists(os.path.join(args.root, "analysis", "cli.py"))
        prefix = "" if legacy else "attneave."
        cli = ["-c", f"import sys; from {prefix}{'analysis.' if legacy else ''}cli import main; sys.exit(main())"]
        cases = [
            ("python -c pass (anchor)", ["-c", "pass"]),
            *([] if legacy else [("import attneave", ["-c", "import attneave"])]),
            (f"import {prefix}stimuli", ["-c", f"import {prefix}stimuli"]),
            (f"import {prefix}analysis", ["-c", f"import {prefix}analysis"]),
            ("attneave --help", [*cli, "--help"]),
            ("attneave surprisal (200 points)", [*cli, "surprisal", src, "-o", os.path.join(d, "u.csv")]),
        ]
        base_wall, base_imp = run(cases[0][1], args.repeats, env)
        print(f"checkout: {args.root or 'installed'}; median of {args.repeats} runs; "
              "import = -X importtime total beyond the anchor's")
        print(f"  {'case':34s} {'wall s':>8s} {'x anchor':>9s} {'import s':>9s}")
        print(f"  {cases[0][0]:34s} {base_wall:8.3f} {1:8.2f}x {0:9.3f}")
        for name, argv in cases[1:]:
            wall, imp = run(argv, args.repeats, env)
            print(f"  {name:34s} {wall:8.3f} {wall / base_wall:8.2f}x {imp - base_imp:9.3f}")
    print("target: --help and a surprisal call well under 0.3 s of import time")


if __name__ == "__main__":
    main()
