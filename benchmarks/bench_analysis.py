"""`attneave analyze` on 100 participants x 100 stimuli x 10 clicks (100,000 clicks).

Data: 100 hand-built stimuli (radial-frequency shapes, ellipses, random
polygons; 512 x 512 images) written as a stimulus set, and 100,000 clicks of
simulated observers (beta = 1, noise 1.5 px) written as a click file. The
analysis uses n = 100 points per contour, a grid of 1024 positions and 1000
circular-shift permutations per stimulus.

Measured in one run:

* ``analyze()`` in memory (mapping, choice-model fits for the tested model
  and its rivals, pooled / per participant / per stimulus, circular KDE,
  Spearman with 1000 circular shifts per stimulus, peaks, AUC, concavity,
  group tests, of which the group and items tests draw a Monte Carlo null of
  1999 replicates of every used click, 2 x 2e8 draws): median of repeats;
  and the Monte Carlo group test alone.
* the command ``attneave analyze`` end to end (read the CSV as text and the
  set, analyse, write every table and summary.json atomically) without
  figures, and with figures (18 PNG pages + report.html).
* the anchor: a bare numpy pass doing the core computation on the same data
  -- brute-force nearest-segment projection of every click, z at the nearest
  point, per-participant mean z and t, the circular density by binning +
  FFT, and the 1000 permutation correlations per stimulus as one matrix
  product of the density ranks with the matrix of shifted prediction ranks;
  and the same pass with the permutations as one FFT cross-correlation. It
  checks that all find the same per-participant effects, correlations and
  null distributions.
* the share of time outside numpy, by cProfile: time in compiled numpy /
  scipy / pandas functions (C functions that cProfile sees as calls) against
  time in Python code and other built-ins. Array arithmetic written with
  operators (``a - b``) does not show up as a call and is counted in the
  Python function that executes it, so the "outside numpy" share is an upper
  bound.

Target (issue 6): under 30 s; ``analyze()`` at most 3x the FFT anchor (issue 13).

``--million``: the command ``attneave analyze`` with default settings on
1,000,000 clicks (1000 participants x 100 stimuli x 10 clicks), run as a
child process, repeated: median wall time and the largest peak memory
(``resource.getrusage(RUSAGE_CHILDREN).ru_maxrss``). Target (issue 11):
under 60 s and 2 GB.

Usage:
``python benchmarks/bench_analysis.py [--participants 100] [--stimuli 100] [--clicks 10] [--repeats 3]``
``python benchmarks/bench_analysis.py --million [--repeats 3]``
``python benchmarks/bench_analysis.py --scale [--repeats 3] [--scale-dir DIR] [--only 100,20000] [--workers 2] [--no-command]``
(see ``bench_scale.py``: 100 to 20,000 stimuli, the 1,000,000-click headline, ``-n 100000``)
"""

from __future__ import annotations

import argparse
import contextlib
import cProfile
import io
import json
import pstats
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy.stats

from attneave.analysis.analyze import analyze
from attneave.analysis.clicks.mapping import predict
from attneave.analysis.clicks.read import read_clicks
from attneave.analysis.simulate.observers import simulate
from attneave.cli import main as cli_main
from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set
from attneave.stimuli.tables import write_table

from _machine import header, load


def make_shapes(count, rng):
    th = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    c = np.array([256.0, 256.0])
    shapes = {}
    for i in range(count):
        kind = i % 5
        if kind < 3:  # radial frequency
            f = rng.integers(2, 8)
            r = 140 * (1 + rng.uniform(0.05, 0.25) * np.sin(f * th + rng.uniform(0, 2 * np.pi)))
            shapes[f"rf_{i:03d}"] = np.c_[c[0] + r * np.cos(th), c[1] + r * np.sin(th)]
        elif kind == 3:  # ellipse
            a, b = 180, rng.uniform(60, 160)
            shapes[f"ellipse_{i:03d}"] = np.c_[c[0] + a * np.cos(th), c[1] + b * np.sin(th)]
        else:  # random star polygon
            k = rng.integers(8, 16)
            a = np.sort(rng.uniform(0, 2 * np.pi, k))
            r = 180 * rng.uniform(0.45, 1.0, k)
            shapes[f"polygon_{i:03d}"] = np.c_[c[0] + r * np.cos(a), c[1] + r * np.sin(a)]
    return shapes


def bare_numpy(x, y, sid, pid, contours, Z, n, grid, shifts, bw, perm="matmul"):
    """The core computation with plain numpy, no validation, no tables.

    perm: 'matmul' computes the permutation correlations as one matrix
    product per stimulus (shifted-rank matrix times density ranks); 'fft' as
    one FFT cross-correlation for all stimuli (what analyze does).
    """
    S = len(contours)
    P = int(pid.max()) + 1
    t = np.empty(len(x))
    for s, pts in enumerate(contours):
        sel = sid == s
        q = np.c_[x[sel], y[sel]]
        a = pts
        d = np.roll(pts, -1, axis=0) - pts
        seg = np.hypot(d[:, 0], d[:, 1])
        cum = np.concatenate(([0.0], np.cumsum(seg)))
        rel = q[:, None, :] - a[None]
        u = np.clip(np.einsum("mij,ij->mi", rel, d) / (seg * seg), 0, 1)
        diff = rel - u[..., None] * d[None]
        jj = np.argmin(np.einsum("mij,mij->mi", diff, diff), axis=1)
        t[sel] = np.mod((cum[jj] + u[np.arange(len(q)), jj] * seg[jj]) / cum[-1], 1.0)
    j = np.mod(np.rint(t * n).astype(np.int64), n)
    z = Z[sid, j]
    mean_z = np.bincount(pid, weights=z, minlength=P) / np.bincount(pid, minlength=P)
    tstat = mean_z.mean() / (mean_z.std(ddof=1) / np.sqrt(P))
    # circular density: linear binning + Gaussian in the Fourier domain
    pos = t * grid
    lo = np.floor(pos).astype(np.int64)
    fr = pos - lo
    hist = np.bincount(sid * grid + lo % grid, weights=1 - fr, minlength=S * grid)
    hist += np.bincount(sid * grid + (lo + 1) % grid, weights=fr, minlength=S * grid)
    k = np.fft.rfftfreq(grid, 1.0 / grid)
    dens = np.fft.irfft(np.fft.rfft(hist.reshape(S, grid), axis=1) * np.exp(-2 * np.pi**2 * k**2 * bw[:, None] ** 2),
                        n=grid, axis=1)
    g = np.arange(grid) / grid
    tp = np.append(np.arange(n) / n, 1.0)
    zg = np.stack([np.interp(g, tp, np.append(Z[s], Z[s, 0])) for s in range(S)])
    rd = scipy.stats.rankdata(np.round(dens / np.abs(dens).max(axis=1, keepdims=True), 9), axis=1)
    ru = scipy.stats.rankdata(np.round(zg / np.abs(zg).max(axis=1, keepdims=True), 9), axis=1)
    rd -= rd.mean(axis=1, keepdims=True)
    ru -= ru.mean(axis=1, keepdims=True)
    norm = np.sqrt((rd * rd).sum(axis=1) * (ru * ru).sum(axis=1))
    rho = (rd * ru).sum(axis=1) / norm
    if perm == "fft":
        c = np.fft.irfft(np.fft.rfft(rd, axis=1) * np.conj(np.fft.rfft(ru, axis=1)), n=grid, axis=1)
        null = c[:, shifts] / norm[:, None]
    else:
        null = np.empty((S, len(shifts)))
        idx = (np.arange(grid)[None, :] - shifts[:, None]) % grid  # row k: prediction shifted by shifts[k]
        for s in range(S):
            null[s] = ru[s][idx] @ rd[s] / norm[s]  # the permutations as one matrix product
    return mean_z, tstat, rho, null


def profile_share(fn):
    pr = cProfile.Profile()
    pr.enable()
    fn()
    pr.disable()
    st = pstats.Stats(pr)
    compiled, python, other = 0.0, 0.0, 0.0
    for (file, _line, name), (_cc, _nc, tt, _ct, _callers) in st.stats.items():
        if file == "~":  # a C function
            if any(k in name for k in ("numpy", "ufunc", "ndarray", "scipy", "pandas", "_libs", "_multiarray")):
                compiled += tt
            else:
                other += tt
        elif any(k in file for k in ("/numpy/", "/scipy/", "/pandas/")):
            python += tt  # Python-level wrappers inside the libraries still run in the interpreter
        else:
            python += tt
    total = compiled + python + other
    project = sum(v[2] for k, v in st.stats.items() if k[2] == "project" and k[0].endswith("contour.py"))
    return total, compiled, python, other, st, project


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--participants", type=int, default=100)
    ap.add_argument("--stimuli", type=int, default=100)
    ap.add_argument("--clicks", type=int, default=10)
    ap.add_argument("--permutations", type=int, default=1000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--million", action="store_true", help="the 1,000,000-click run of the command (issue 11)")
    ap.add_argument("--scale", action="store_true",
                    help="analyze() from 100 to 20,000 stimuli and 1,000,000 clicks: time and peak RSS (issue 25)")
    ap.add_argument("--scale-dir", default=None, help="keep (and reuse) the --scale data here")
    ap.add_argument("--only", type=lambda v: [int(x) for x in v.split(",")], default=None,
                    help="--scale: only the cases of these numbers of stimuli, e.g. 100,20000")
    ap.add_argument("--no-command", action="store_true", help="--scale: analyze() only, not the command end to end")
    ap.add_argument("--workers", type=int, default=2,
                    help="--scale: the command's --workers (its predictions), default 2 (this machine's cores)")
    args = ap.parse_args(argv)
    if args.million:
        return million(args)
    if args.scale:
        from bench_scale import scale

        return scale(args, header, load)
    header("bench_analysis: analyze() against its bare-numpy anchor")
    n, grid = 100, 1024
    rng = np.random.default_rng(args.seed)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        write_stimulus_set(tmp / "set", make_shapes(args.stimuli, rng))
        stimset = read_stimulus_set(tmp / "set")
        pred = predict(stimset, n=n)
        t0 = time.perf_counter()
        df, _ = simulate(pred, args.participants, args.clicks, 1.0, seed=args.seed, noise=1.5)
        t_sim = time.perf_counter() - t0
        write_table(df, tmp / "clicks.csv", float_format="%.17g")
        clicks = read_clicks(tmp / "clicks.csv")
        N = len(clicks)

        def run_analysis():
            return analyze(clicks, stimset, n=n, permutations=args.permutations, grid=grid)

        times, cpu_an = [], []
        for _ in range(args.repeats):
            t0, c0 = time.perf_counter(), time.process_time()
            res = run_analysis()
            times.append(time.perf_counter() - t0)
            cpu_an.append(time.process_time() - c0)
        t_an = statistics.median(times)

        # the Monte Carlo null of the group test alone (the items test costs the same)
        from attneave.analysis.models.group import mean_z_test

        U = res.summary["n_used"]
        Zs = np.stack([pred[s].z["surprisal"] for s in stimset.ids])
        used = res.clicks[~res.clicks["excluded"]]
        sidx_u = used["stimulus_id"].map({s: i for i, s in enumerate(stimset.ids)}).to_numpy()
        pidx_u = used["participant"].map({p: i for i, p in enumerate(sorted(used["participant"].unique()))}).to_numpy()
        t0 = time.perf_counter()
        mc = mean_z_test(Zs, sidx_u, pidx_u, used["z"].to_numpy(float), replicates=1999,
                         rng=np.random.default_rng(0))
        t_mc = time.perf_counter() - t0
        assert abs(mc["statistic"] - res.summary["group"]["statistic"]) < 1e-9 * abs(mc["statistic"])

        # the anchor on the same clicks (image coordinates, all used)
        ids = stimset.ids
        x = df["x"].to_numpy()
        y = df["y"].to_numpy()
        sid = df["stimulus_id"].map({s: i for i, s in enumerate(ids)}).to_numpy()
        pid = df["participant"].map({p: i for i, p in enumerate(sorted(df["participant"].unique()))}).to_numpy()
        contours = [stimset.contours[s].points for s in ids]
        Z = np.stack([pred[s].z["surprisal"] for s in ids])
        bw = np.full(len(ids), 0.02)
        from attneave.analysis.models.circular import shift_indices

        shifts = shift_indices(grid, args.permutations)
        tb, tf, cpu_f = [], [], []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            mean_z, tstat, rho, null = bare_numpy(x, y, sid, pid, contours, Z, n, grid, shifts, bw, "matmul")
            tb.append(time.perf_counter() - t0)
            t0, c0 = time.perf_counter(), time.process_time()
            _, _, rho_f, null_f = bare_numpy(x, y, sid, pid, contours, Z, n, grid, shifts, bw, "fft")
            tf.append(time.perf_counter() - t0)
            cpu_f.append(time.process_time() - c0)
        t_bare, t_bare_fft = statistics.median(tb), statistics.median(tf)
        np.testing.assert_allclose(null, null_f, atol=1e-9)
        assert res.summary["n_used"] == N, "benchmark clicks were excluded"
        np.testing.assert_allclose(res.per_participant["mean_z"], mean_z, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(res.per_stimulus["spearman_rho"], rho, atol=1e-9)
        assert abs(res.summary["group"]["statistic"] - tstat) < 1e-6 * abs(tstat)

        # the permutation correlations alone: FFT (as analyze does) vs the matrix product
        from attneave.analysis.models.circular import circular_spearman

        dens, zg = res.profiles["density"], res.profiles["z"]
        t0 = time.perf_counter()
        circular_spearman(dens, zg, shifts)
        t_fft = time.perf_counter() - t0
        idx = (np.arange(grid)[None, :] - shifts[:, None]) % grid
        t0 = time.perf_counter()
        for s in range(len(ids)):
            rd = scipy.stats.rankdata(dens[s])
            ru = scipy.stats.rankdata(zg[s])
            _ = ru[idx] @ rd
        t_mat = time.perf_counter() - t0

        # the command line, end to end
        t0 = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()):
            rc = cli_main(["analyze", str(tmp / "clicks.csv"), "--stimuli", str(tmp / "set"), "-o", str(tmp / "out"),
                           "--permutations", str(args.permutations), "--no-figures"])
        t_cli = time.perf_counter() - t0
        assert rc == 0
        t0 = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()):
            rc = cli_main(["analyze", str(tmp / "clicks.csv"), "--stimuli", str(tmp / "set"), "-o", str(tmp / "outf"),
                           "--permutations", str(args.permutations)])
        t_cli_fig = time.perf_counter() - t0
        assert rc == 0
        n_figs = len(list((tmp / "outf" / "figures").iterdir()))

        total, compiled, python, other, st, project = profile_share(run_analysis)

    print(f"{args.participants} participants x {args.stimuli} stimuli x {args.clicks} clicks = {N:,} clicks; "
          f"n = {n}, grid = {grid}, {len(shifts)} circular shifts per stimulus; median of {args.repeats}")
    print(f"  simulate (100,000 clicks, noise 1.5 px)          {t_sim:7.2f} s")
    print(f"  anchor: bare numpy, permutations by matmul         {t_bare:7.2f} s   1.00x")
    print(f"  anchor: bare numpy, permutations by FFT            {t_bare_fft:7.2f} s   {t_bare_fft / t_bare:.2f}x")
    print(f"  analyze() in memory                               {t_an:7.2f} s   {t_an / t_bare:.2f}x"
          f"   ({t_an / t_bare_fft:.2f}x the FFT anchor)")
    print(f"    CPU time (process_time, less sensitive to other processes): analyze() "
          f"{statistics.median(cpu_an):.2f} s, FFT anchor {statistics.median(cpu_f):.2f} s, ratio "
          f"{statistics.median(cpu_an) / statistics.median(cpu_f):.2f}x; load average now {load():.2f}")
    print(f"    the Monte Carlo group test alone (R = 1999, {U:,} clicks)  {t_mc:5.2f} s (analyze draws the items "
          f"test's null from the same draws)")
    print(f"  attneave analyze, CLI, no figures                 {t_cli:7.2f} s   {t_cli / t_bare:.2f}x")
    print(f"  attneave analyze, CLI, with {n_figs} figures          {t_cli_fig:7.2f} s   {t_cli_fig / t_bare:.2f}x")
    print(f"  permutation correlations only: FFT {t_fft * 1e3:.0f} ms vs matrix product {t_mat * 1e3:.0f} ms "
          f"({t_mat / t_fft:.1f}x)")
    print(f"  cProfile of analyze() ({total:.2f} s under the profiler): compiled numpy/scipy/pandas "
          f"{compiled / total:.0%}, Python code {python / total:.0%}, other built-ins {other / total:.0%}; "
          f"outside numpy <= {(python + other) / total:.0%} (operator arithmetic counts as Python)")
    print(f"    of that Python share, {project / total:.0%} of all time is the own time of Contour.project, whose body "
          f"is array expressions (q - a, clip, products) that numpy evaluates; the rest of Python is "
          f"{(python - project) / total:.0%}")
    buf = io.StringIO()
    st.stream = buf
    st.sort_stats("tottime").print_stats(8)
    print("  top functions by own time:")
    for line in buf.getvalue().splitlines():
        if line.strip() and (line.strip()[0].isdigit()):
            print("   ", line.strip()[:150])
    print(f"  by the FFT anchor: {max(0.0, 1 - t_bare_fft / t_an):.0%} of analyze()'s time goes beyond the bare numpy "
          f"core (validation, exclusion reasons, tables, rival models, per-participant/stimulus fits, tests)")
    ok = t_cli < 30
    print(f"target: under 30 s for the analysis of 100,000 clicks -> {'met' if ok else 'NOT met'} "
          f"({t_cli:.1f} s end to end without figures, {t_cli_fig:.1f} s with)")


def million(args, participants=1000, stimuli=100, clicks=10):
    """`attneave analyze` with default settings on 1,000,000 clicks, in a child process."""
    header("bench_analysis --million: attneave analyze on 1,000,000 clicks, default settings")
    rng = np.random.default_rng(args.seed)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        write_stimulus_set(tmp / "set", make_shapes(stimuli, rng))
        pred = predict(read_stimulus_set(tmp / "set"), n=100)
        df, _ = simulate(pred, participants, clicks, 1.0, seed=args.seed, noise=1.5)
        write_table(df, tmp / "clicks.csv", float_format="%.17g")
        del df, pred
        times, loads = [], []
        for r in range(args.repeats):
            loads.append(load())
            t0 = time.perf_counter()
            proc = subprocess.run([sys.executable, "-m", "attneave.cli", "analyze", str(tmp / "clicks.csv"), "--stimuli",
                                   str(tmp / "set"), "-o", str(tmp / f"out{r}")], capture_output=True, text=True)
            times.append(time.perf_counter() - t0)
            if proc.returncode != 0:
                raise SystemExit(proc.stderr)
        usage = resource.getrusage(resource.RUSAGE_CHILDREN)
        rss_gb = usage.ru_maxrss / 2**20  # kB on Linux
        cpu = (usage.ru_utime + usage.ru_stime) / args.repeats
        n_used = json.loads((tmp / "out0" / "summary.json").read_text())["n_used"]
    t = statistics.median(times)
    print(f"{participants * stimuli * clicks:,} clicks ({n_used:,} used), {args.repeats} runs: median {t:.1f} s "
          f"(runs {', '.join(f'{v:.1f}' for v in times)}; load average at their start "
          f"{', '.join(f'{v:.2f}' for v in loads)}); CPU time per run {cpu:.1f} s (mean; less sensitive to other "
          f"processes than wall time); peak memory {rss_gb:.2f} GB")
    print(f"target: under 60 s and 2 GB -> {'met' if t < 60 and rss_gb < 2 else 'NOT met'}")
    print("progress as the command prints it on stderr (last run):")
    print("  " + proc.stderr.strip().replace("\r", "\n").splitlines()[-1] if proc.stderr.strip() else "  (none)")


if __name__ == "__main__":
    main()
