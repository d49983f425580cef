"""``bench_analysis.py --scale``: analyze() from 100 to 20,000 stimuli, time and peak memory per run.

Data: radial-frequency contours (360 points, 512 x 512 images) written as a
stimulus set, their predictions at n = 100 (made once and cached: the
prediction stage is timed apart, it grows linearly with the stimuli), and
clicks of simulated observers (beta = 1, noise 1.5 px;
:func:`attneave.analysis.simulate.observers.simulate`). Every run is a child
process: ``analyze()`` with all models (default settings otherwise: 1000
circular shifts, grid 1024, 1999 Monte Carlo replicates), its wall time, and
its peak resident memory from ``os.wait4`` (``ru_maxrss`` of that child
alone); the FFT anchor of :func:`bench_analysis.bare_numpy` runs on the same
clicks in its own child, and the ratio is printed. Repeats give the median
time and the largest peak; the load average at the start of each run is
printed (2 shared cores: a loaded machine stretches wall time, not memory).

Targets (issue 25): 1,000,000 clicks from 200 participants on 5,000 stimuli
under 60 s and 2 GB; 20,000 stimuli with 160,000 clicks under 60 s and 4 GB;
``-n 100000`` on 720 clicks runs under 2 GB or is refused in one line before
any heavy allocation.
"""

from __future__ import annotations

import json
import os
import pickle
import statistics
import sys
import time
from pathlib import Path

import numpy as np

#: (stimuli, participants, clicks per participant per stimulus, label)
CASES = [(100, 8, 1, "100 stimuli"), (1000, 8, 1, "1,000 stimuli"), (5000, 8, 1, "5,000 stimuli"),
         (20000, 8, 1, "20,000 stimuli"), (5000, 200, 1, "headline: 1,000,000 clicks")]


def scale_shapes(count, seed=0):
    """Radial-frequency contours (simple, smooth, never self-crossing)."""
    rng = np.random.default_rng(seed)
    th = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    out = {}
    for i in range(count):
        f = rng.integers(2, 8)
        r = 140 * (1 + rng.uniform(0.05, 0.25) * np.sin(f * th + rng.uniform(0, 2 * np.pi)))
        out[f"rf_{i:05d}"] = np.c_[256 + r * np.cos(th), 256 + r * np.sin(th)]
    return out


#: Distinct contours: stimulus i has the contour of base shape i mod BASE, so that the prediction
#: (seconds per stimulus, mostly the medial axis) is made once per base shape; the analysis does
#: not know or care that contours repeat.
BASE = 500


def prepare(root, S, P, K, n=100):
    """The stimulus set (pickled), its predictions (pickled) and the click file of one case.

    Returns the set's directory, the click file and the seconds per stimulus of predict().
    """
    import dataclasses

    from attneave.analysis.clicks.mapping import predict
    from attneave.analysis.simulate.observers import simulate
    from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set
    from attneave.stimuli.tables import write_table

    sdir = root / f"set_{S}"
    bdir = root / f"base_{BASE}_n{n}"
    if not (bdir / "predictions.pkl").exists():
        write_stimulus_set(bdir, scale_shapes(BASE), size=(512, 512))
        t0 = time.perf_counter()
        base = predict(read_stimulus_set(bdir), n=n)
        per = (time.perf_counter() - t0) / BASE
        with open(bdir / "predictions.pkl", "wb") as f:
            pickle.dump((base, per), f)
    with open(bdir / "predictions.pkl", "rb") as f:
        base, per = pickle.load(f)
    if not (sdir / "predictions.pkl").exists():
        shapes = scale_shapes(BASE)
        keys = list(shapes)
        ids = [f"rf_{i:05d}" for i in range(S)]
        write_stimulus_set(sdir, {sid: shapes[keys[i % BASE]] for i, sid in enumerate(ids)}, size=(512, 512))
        stimset = read_stimulus_set(sdir)
        pred = {sid: dataclasses.replace(base[keys[i % BASE]], stimulus_id=sid) for i, sid in enumerate(ids)}
        with open(sdir / "stimset.pkl", "wb") as f:
            pickle.dump(stimset, f)
        with open(sdir / "predictions.pkl", "wb") as f:
            pickle.dump(pred, f)
    cfile = root / f"clicks_{S}_{P}_{K}.csv"
    if not cfile.exists():
        with open(sdir / "predictions.pkl", "rb") as f:
            pred = pickle.load(f)
        df, _ = simulate(pred, P, K, 1.0, seed=0, noise=1.5)
        write_table(df, cfile, float_format="%.10g")
    return sdir, cfile, per


def child(argv):
    """In the child: one run (analyze or the anchor) on a case; writes a JSON line to argv[3]."""
    kind, sdir, cfile, out = argv[0], Path(argv[1]), Path(argv[2]), Path(argv[3])
    from attneave.analysis.analyze import analyze
    from attneave.analysis.clicks.read import read_clicks

    with open(sdir / "stimset.pkl", "rb") as f:
        stimset = pickle.load(f)
    clicks = read_clicks(cfile)
    with open(sdir / "predictions.pkl", "rb") as f:
        pred = pickle.load(f)
    t0 = time.perf_counter()
    if kind == "analyze":
        res = analyze(clicks, stimset, predictions=pred, quiet=True)
        extra = dict(models_run=res.summary["models_run"], skipped=res.summary["models_skipped"],
                     mixed_beta=(res.summary.get("mixed") or {}).get("beta"))
    else:
        from bench_analysis import bare_numpy

        from attneave.analysis.models.circular import shift_indices

        ids = list(stimset.ids)
        x, y = clicks["x"].to_numpy(float), clicks["y"].to_numpy(float)
        sid = clicks["stimulus_id"].map({s: i for i, s in enumerate(ids)}).to_numpy()
        pid = clicks["participant"].map({p: i for i, p in enumerate(sorted(clicks["participant"].unique()))}).to_numpy()
        contours = [stimset.contours[s].points for s in ids]
        Z = np.stack([pred[s].z["surprisal"] for s in ids])
        bare_numpy(x, y, sid, pid, contours, Z, 100, 1024, shift_indices(1024, 1000), np.full(len(ids), 0.02), "fft")
        extra = {}
    out.write_text(json.dumps(dict(seconds=time.perf_counter() - t0, **extra)))


def measured(args):
    """Run `args` in a fresh child and return (stdout, stderr, rc, wall, peak RSS in bytes)."""
    t0 = time.perf_counter()
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child
        os.execv(args[0], args)
    _, status, usage = os.wait4(pid, 0)
    return os.waitstatus_to_exitcode(status), time.perf_counter() - t0, usage.ru_maxrss * 1024


def scale(args, header, load):
    """The --scale table."""
    import tempfile

    header("bench_analysis --scale: analyze() from 100 to 20,000 stimuli; each run a child process")
    here = Path(__file__).resolve().parent
    keep = Path(args.scale_dir) if args.scale_dir else Path(tempfile.mkdtemp(prefix="attneave_scale_"))
    keep.mkdir(parents=True, exist_ok=True)
    cases = [c for c in CASES if not args.only or c[0] in args.only]
    print(f"data in {keep}; repeats {args.repeats}; n = 100, grid 1024, 1000 shifts, R = 1999, all models")
    print(f"{'case':28s} {'clicks':>10s} {'predict':>8s} {'analyze':>9s} {'peak RSS':>9s} {'anchor':>8s} "
          f"{'ratio':>6s} {'command':>8s} {'its RSS':>8s}  load at start / models")
    for S, P, K, label in cases:
        sdir, cfile, t_pred = prepare(keep, S, P, K)
        times, peaks, loads, anchors, walls, rss_cmd, info = [], [], [], [], [], [], {}
        for _ in range(args.repeats):
            loads.append(load())
            out_file = keep / "child.json"
            rc, wall, rss = measured([sys.executable, str(here / "bench_scale.py"), "analyze", str(sdir), str(cfile),
                                      str(out_file)])
            if rc != 0:
                raise SystemExit(f"{label}: analyze failed (exit {rc})")
            info = json.loads(out_file.read_text())
            times.append(info["seconds"])
            peaks.append(rss)
            rc, _, _ = measured([sys.executable, str(here / "bench_scale.py"), "anchor", str(sdir), str(cfile),
                                 str(out_file)])
            anchors.append(json.loads(out_file.read_text())["seconds"] if rc == 0 else float("nan"))
            if args.no_command:
                continue
            rc, wall, rss = measured(["/bin/sh", "-c", f"{sys.executable} -m attneave.cli analyze {cfile} --stimuli "
                                      f"{sdir} -o {keep / 'out_command'} --force --no-figures --quiet "
                                      f"--workers {args.workers} > /dev/null"])
            if rc != 0:
                raise SystemExit(f"{label}: the command failed (exit {rc})")
            walls.append(wall)
            rss_cmd.append(rss)
        t, a = statistics.median(times), statistics.median(anchors)
        w = statistics.median(walls) if walls else float("nan")
        rss_cmd = rss_cmd or [float("nan")]
        pred_txt = f"{t_pred * S:7.0f}s"
        print(f"{label:28s} {S * P * K:>10,d} {pred_txt:>8s} {t:8.1f}s {max(peaks) / 2**30:7.2f}GB {a:7.1f}s "
              f"{t / a:5.1f}x {w:7.1f}s {max(rss_cmd) / 2**30:6.2f}GB  "
              f"{', '.join(f'{v:.1f}' for v in loads)} / {','.join(info.get('models_run', []))}"
              + (f" (skipped: {info['skipped']})" if info.get("skipped") else ""), flush=True)
    print("analyze = analyze() given the cached predictions (in-memory clicks; reading CSV and writing outputs "
          "not included); predict = predict() of the whole set, extrapolated from its seconds per stimulus on "
          f"{BASE} distinct contours (not in analyze's time: a set is predicted once); peak RSS of the "
          "analyze child (imports and data included); anchor = bare-numpy FFT pass on the same clicks; "
          f"command = 'attneave analyze CSV --stimuli SET -o OUT --no-figures --workers {args.workers}' end to end "
          "(reading the CSV and the set's contour files, predictions, analysis, every table and report.html), "
          "its peak RSS that of its largest process")
    if not args.only or 36 in args.only:  # --only 36: the -n 100000 case alone
        big_n(keep, load)


def big_n(keep, load):
    """``attneave analyze -n 100000`` on 720 clicks: runs under 2 GB, or is refused in one line."""
    sdir, cfile, _ = prepare(keep, 36, 20, 1)
    out = keep / "out_n100000"
    err_file = keep / "n100000.err"
    l0 = load()
    rc, wall, rss = measured(["/bin/sh", "-c", f"{sys.executable} -m attneave.cli analyze {cfile} --stimuli {sdir} "
                                               f"-o {out} --force -n 100000 --no-figures --quiet 2> {err_file}"])
    err = err_file.read_text().strip().splitlines()
    what = ("refused: " + err[-1]) if rc == 2 else ("ran" if rc == 0 else f"failed (exit {rc}): {err[-1:]}")
    print(f"-n 100000 on 720 clicks (36 stimuli): exit {rc}, {wall:.1f} s, peak RSS {rss / 2**30:.2f} GB "
          f"(load {l0:.1f}): {what}")


if __name__ == "__main__":
    child(sys.argv[1:])
