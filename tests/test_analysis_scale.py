"""Analysis that scales with the study: the sparse mixed model against a dense reference, its
analytic gradient, the memory plan (refusal and skipped models), progress lines on a log, and a
20,000-stimulus design that builds no stimuli x stimuli array."""

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest
import scipy.optimize

from attneave.analysis.models.choice import standardize
from attneave.analysis.models.mixed import CumulantTable, fit_mixed, laplace_loglik
from attneave.cli import main
from attneave.stimuli.stimulus_set import write_stimulus_set


def _crossed(seed, S=8, n=30, G=6, K=3, keep=0.75):
    """Clicks of G participants on a random subset of S stimuli (crossed slopes, unbalanced)."""
    rng = np.random.default_rng(seed)
    Z = standardize(rng.gamma(1.0, size=(S, n)))
    u, v = rng.normal(0, 0.3, G), rng.normal(0, 0.4, S)
    st, pa, j = [], [], []
    for p in range(G):
        for s in range(S):
            if rng.random() > keep:
                continue
            x = (0.6 + u[p] + v[s]) * Z[s]
            w = np.exp(x - x.max())
            j.append(rng.choice(n, size=K, p=w / w.sum()))
            st += [s] * K
            pa += [p] * K
    return Z, np.array(st), np.array(pa), np.concatenate(j)


def _dense_laplace(Z, st, pa, j, lsp, lss, table):
    """The Laplace log-likelihood with the full dense (G + S + 1) Hessian: the reference."""
    su, s_of = np.unique(st, return_inverse=True)
    _, p_of = np.unique(pa, return_inverse=True)
    S, G = len(su), p_of.max() + 1
    R = G + S + 1
    a = np.zeros((len(st), R))  # each click's indicator of (u_p, v_s, beta)
    a[np.arange(len(st)), p_of] = 1
    a[np.arange(len(st)), G + s_of] = 1
    a[:, -1] = 1
    prior = np.r_[np.full(G, np.exp(-2 * lsp)), np.full(S, np.exp(-2 * lss)), 0.0]
    x = np.zeros(R)
    zc = Z[st, j]
    for _ in range(100):
        b = a @ x
        K, E, V = table(st, b)
        g = a.T @ (zc - E) - prior * x
        H = a.T @ (a * V[:, None]) + np.diag(prior)
        dx = np.linalg.solve(H, g)
        x = x + dx / max(1.0, np.abs(dx).max())  # steps of at most 1: plain Newton may overshoot
        if np.abs(dx).max() < 1e-13:
            break
    b = a @ x
    K, E, V = table(st, b)
    f = (b * zc - K).sum() - 0.5 * (prior * x * x).sum()
    H = a.T @ (a * V[:, None]) + np.diag(prior)
    return f - G * lsp - S * lss - 0.5 * np.linalg.slogdet(H)[1], x[-1], np.linalg.inv(H)[-1, -1]


@pytest.mark.parametrize("seed,shape", [(0, dict(S=8, G=6)), (1, dict(S=5, G=9))])
def test_sparse_mixed_model_equals_the_dense_reference(seed, shape):
    Z, st, pa, j = _crossed(seed, **shape)
    tab = CumulantTable(Z)
    # the dense reference maximised by Nelder-Mead to 1e-10 in the log sds, no gradient at all
    ref = scipy.optimize.minimize(lambda t: -_dense_laplace(Z, st, pa, j, t[0], t[1], tab)[0], np.log([0.3, 0.3]),
                                  method="Nelder-Mead", bounds=[(-7, np.log(5))] * 2,
                                  options=dict(xatol=1e-10, fatol=1e-13, maxiter=2000))
    ll, beta, var = _dense_laplace(Z, st, pa, j, *ref.x, tab)
    f = fit_mixed(Z, st, pa, j, table=tab)
    assert f["estimable"] and f["converged"]
    assert f["loglik"] == pytest.approx(ll, abs=1e-8)
    assert f["beta"] == pytest.approx(beta, abs=1e-6)
    assert f["se"] == pytest.approx(np.sqrt(var), abs=1e-6)
    assert f["sd_participant"] == pytest.approx(np.exp(ref.x[0]), abs=1e-5)
    assert f["sd_stimulus"] == pytest.approx(np.exp(ref.x[1]), abs=1e-5)


@pytest.mark.parametrize("sds", [(0.2, 0.5), (0.9, 0.1)])
def test_laplace_gradient_matches_finite_differences_and_the_dense_value(sds):
    Z, st, pa, j = _crossed(2, S=7, G=10)
    tab = CumulantTable(Z)
    ll, grad, _ = laplace_loglik(Z, st, pa, j, *sds, table=tab)
    assert ll == pytest.approx(_dense_laplace(Z, st, pa, j, *np.log(sds), tab)[0], abs=1e-8)
    e = 1e-5
    fd = []
    for k in range(2):
        hi, lo = np.log(sds), np.log(sds)
        hi[k] += e
        lo[k] -= e
        fd.append((laplace_loglik(Z, st, pa, j, *np.exp(hi), table=tab)[0]
                   - laplace_loglik(Z, st, pa, j, *np.exp(lo), table=tab)[0]) / (2 * e))
    np.testing.assert_allclose(grad, fd, rtol=1e-5, atol=1e-6)
    assert np.abs(grad).max() > 1e-2  # away from the optimum: the check has something to check


# ------------------------------------------------------------------ the command
def _shapes(count=4):
    th = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    return {f"rf_{i}": np.c_[200 + (90 + 12 * np.sin((3 + i) * th)) * np.cos(th),
                             200 + (90 + 12 * np.sin((3 + i) * th)) * np.sin(th)] for i in range(count)}


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    from attneave.analysis.clicks.mapping import predict
    from attneave.analysis.simulate.observers import simulate
    from attneave.stimuli.stimulus_set import read_stimulus_set
    from attneave.stimuli.tables import write_table

    d = tmp_path_factory.mktemp("scale")
    write_stimulus_set(d / "set", _shapes(), size=(400, 400))
    df, _ = simulate(predict(read_stimulus_set(d / "set"), n=40), 4, 5, 1.0, seed=0)
    write_table(df, d / "clicks.csv")
    return d


def _run(small, out, *extra):
    return main(["analyze", str(small / "clicks.csv"), "--stimuli", str(small / "set"), "-o", str(out), "-n", "40",
                 "--permutations", "9", "--group-simulations", "9", "--grid", "64", "--no-figures", *extra])


def test_a_run_that_does_not_fit_is_refused_in_one_line_before_the_predictions(small, tmp_path, capsys,
                                                                                monkeypatch):
    import attneave.analysis.analyze as an
    import attneave.analysis.budget as budget

    monkeypatch.setattr(budget, "available_bytes", lambda: 50e6)
    monkeypatch.setattr(an, "predict", lambda *a, **k: pytest.fail("predictions made before the refusal"))
    capsys.readouterr()
    assert _run(small, tmp_path / "out", "-n", "100000") == 2
    err = capsys.readouterr().err.strip().splitlines()
    lines = [x for x in err if "error" in x]
    assert len(lines) == 1 and "-n" in lines[0] and "GB" in lines[0], err
    assert not (tmp_path / "out").exists()


def test_the_mixed_model_is_left_out_when_it_alone_does_not_fit_and_refused_when_named(small, tmp_path, capsys,
                                                                                      monkeypatch):
    import attneave.analysis.budget as budget

    sizes = dict(n_stimuli=4, n=40, n_clicks=80, n_participants=4, grid=64, permutations=9)
    e = budget.estimate(**sizes)
    core = sum(v for k, v in e.items() if k != "mixed")
    monkeypatch.setattr(budget, "available_bytes", lambda: core + e["mixed"] / 2)
    assert _run(small, tmp_path / "out") == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert "mixed" not in s["models_run"] and "mixed" not in s
    assert s["models_skipped"]["mixed"].startswith("left out") and "GB" in s["models_skipped"]["mixed"]
    html = (tmp_path / "out" / "report.html").read_text()
    assert "Models not run: mixed" in html
    capsys.readouterr()
    assert _run(small, tmp_path / "out2", "--models", "mixed") == 2
    assert "--models" in capsys.readouterr().err


def test_models_option_runs_only_the_named_models_and_records_the_rest(small, tmp_path):
    assert _run(small, tmp_path / "out", "--models", "choice,group") == 0
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["models_run"] == ["choice", "group"]
    assert set(s["models_skipped"]) == {"rivals", "joint", "mixed"}  # blurred applies only with --click-sd
    assert "mixed" not in s and s["predictors"] == {}
    assert set(s["models"]) == {"surprisal", "uniform"}  # no rivals fitted
    assert s["group"]["p_value"] is not None  # the Monte Carlo null ran
    assert _run(small, tmp_path / "out2", "--models", "mixed") == 0
    s2 = json.loads((tmp_path / "out2" / "summary.json").read_text())
    assert s2["models_run"] == ["choice", "mixed"] and s2["mixed"]["estimable"] in (True, False)
    assert s2["group"]["p_value"] is None and s2["beta_hat"] == pytest.approx(s["beta_hat"], abs=1e-12)


def test_the_mixed_model_runs_with_one_blas_thread(small, tmp_path, monkeypatch):
    """Many small factorisations: OpenBLAS's threads wait for each other when the other core is busy
    (a 201 x 201 Cholesky took 0.16 s instead of 0.12 ms), so the analysis limits BLAS to one thread."""
    from threadpoolctl import threadpool_info

    import attneave.analysis.analyze as an

    seen = []
    real = an.fit_mixed

    def spy(*a, **k):
        seen.extend(i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas")
        return real(*a, **k)

    monkeypatch.setattr(an, "fit_mixed", spy)
    assert _run(small, tmp_path / "out", "--models", "mixed") == 0
    assert seen and set(seen) == {1}, seen


def test_bad_models_are_refused_in_one_line(small, tmp_path, capsys):
    capsys.readouterr()
    assert _run(small, tmp_path / "out", "--models", "mixed,bogus") == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--models" in err and "bogus" in err


def test_progress_lines_reach_a_log_and_quiet_silences_them(small, tmp_path, capsys, monkeypatch):
    import attneave.stimuli.progress as progress

    monkeypatch.setattr(progress, "THRESHOLD", 0.0)  # every stage counts as slow
    capsys.readouterr()
    assert _run(small, tmp_path / "out") == 0
    err = capsys.readouterr().err  # captured: not a terminal, so no bar, only lines
    for stage in ("reading clicks", "predictions", "mapping clicks", "choice models", "mixed model", "writing"):
        assert f"attneave analyze: {stage}" in err, err
    assert "\r" not in err
    assert _run(small, tmp_path / "out2", "--quiet") == 0
    err = capsys.readouterr().err
    assert "mapping clicks" not in err and "predictions" not in err and "reading" not in err


def test_a_slow_stage_is_announced_while_it_runs():
    import io
    import time

    from attneave.stimuli.progress import Stages

    out = io.StringIO()
    with Stages("demo", file=out, threshold=0.05) as st:
        st.stage("quick")
        st.stage("slow")
        time.sleep(0.3)
        assert "attneave demo: slow (" in out.getvalue()  # before the stage ends
    lines = out.getvalue().splitlines()
    assert not any("quick" in x for x in lines)  # under the threshold: nothing
    assert lines[-1].startswith("attneave demo: slow done in")
    quiet = io.StringIO()
    with Stages("demo", file=quiet, threshold=0.0, quiet=True) as st:
        st.stage("slow")
    assert quiet.getvalue() == ""


def test_twenty_thousand_stimuli_build_no_stimuli_by_stimuli_array():
    # under an address-space limit of 1.5 GB beyond what the imports take, a 20,000 x 20,000 array
    # (3.2 GB) cannot be made: the per-stimulus table and the mixed model must do without one
    code = textwrap.dedent("""
        import resource
        from types import SimpleNamespace
        import numpy as np
        import scipy.sparse
        from attneave.analysis.models.design import Design
        from attneave.analysis.models.mixed import fit_mixed
        from attneave.analysis.report.tables import stimulus_table
        from attneave.analysis.models.choice import standardize

        S, n, G = 20000, 8, 4
        rng = np.random.default_rng(0)
        Z = standardize(rng.normal(size=(S, n)))
        sidx = np.repeat(np.arange(S), G)
        pidx = np.tile(np.arange(G), S)
        j = rng.integers(0, n, len(sidx))
        with open("/proc/self/status") as f:
            vm = next(int(x.split()[1]) * 1024 for x in f if x.startswith("VmSize:"))
        resource.setrlimit(resource.RLIMIT_AS, (vm + (3 << 29), resource.RLIM_INFINITY))
        ids = [f"s{i}" for i in range(S)]
        d = Design(ids=ids, participants=list(range(G)), sidx=sidx, pidx=pidx, t=j / n, j=j, zc=Z[sidx, j],
                   perim=np.full(S, 100.0), npts=n, Z=Z, Zs={"surprisal": Z}, sign=np.ones((S, n)),
                   Ms=np.bincount(sidx, minlength=S).astype(float),
                   Mgs=scipy.sparse.csr_matrix((np.ones(len(sidx)), (pidx, sidx)), shape=(G, S)),
                   Cs=np.zeros((S, n)))
        import pandas as pd
        mapped = pd.DataFrame(dict(stimulus_id=np.asarray(ids)[sidx]))
        pred = {s: SimpleNamespace(predictors={"surprisal": Z[i]}) for i, s in enumerate(ids)}
        feats = dict(hit=np.zeros(len(sidx), bool), chance=np.zeros(S), npeaks=np.ones(S, int),
                     concave=np.zeros(len(sidx), bool), convex=np.ones(len(sidx), bool),
                     concave_len=np.zeros(S), convex_len=np.ones(S))
        corr = dict(rho=np.zeros(S), p=np.ones(S), shifts=np.arange(3))
        per_s = stimulus_table(d, mapped, pred, SimpleNamespace(manifest=None), np.full(len(sidx), 0.5), feats,
                               corr, np.ones(S), np.ones(S))
        assert len(per_s) == S and np.isfinite(per_s["beta_hat"]).sum() > S // 2
        m = fit_mixed(Z, sidx, pidx, j)
        assert m["n_stimuli"] == S and m["estimable"], m
        print("ok", resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024, "MB")
    """)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0 and r.stdout.startswith("ok"), r.stderr[-2000:]


def test_predictions_in_worker_processes_equal_those_of_one(tmp_path):
    from attneave.analysis.clicks.mapping import PREDICT_CHUNK, predict
    from attneave.stimuli.stimulus_set import read_stimulus_set

    count = 2 * PREDICT_CHUNK + 5  # three chunks, the last one short
    write_stimulus_set(tmp_path / "set", _shapes(count), size=(400, 400))
    stimset = read_stimulus_set(tmp_path / "set")
    done = []
    one = predict(stimset, n=40)
    two = predict(stimset, n=40, workers=2, progress=done.append)
    assert list(two) == list(stimset.ids) == list(one)
    assert sorted(done) == sorted([PREDICT_CHUNK, PREDICT_CHUNK, 5])
    for sid in one:
        assert one[sid].predictors.keys() == two[sid].predictors.keys()
        for key in one[sid].predictors:
            assert np.array_equal(one[sid].predictors[key], two[sid].predictors[key]), (sid, key)
            assert np.array_equal(one[sid].z[key], two[sid].z[key])
        assert np.array_equal(one[sid].sign, two[sid].sign)
    # the shapes differ, so equality above is not that of one repeated stimulus
    assert not np.array_equal(one["rf_0"].predictors["surprisal"], one["rf_1"].predictors["surprisal"])


def test_analyze_with_two_workers_writes_the_same_tables(small, tmp_path, capsys):
    assert _run(small, tmp_path / "one") == 0
    assert _run(small, tmp_path / "two", "--workers", "2") == 0
    for name in ("clicks.csv", "per_participant.csv", "per_stimulus.csv"):
        assert (tmp_path / "one" / name).read_bytes() == (tmp_path / "two" / name).read_bytes(), name
    capsys.readouterr()
    assert _run(small, tmp_path / "bad", "--workers", "0") == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--workers" in err and not (tmp_path / "bad").exists()


def test_the_report_marks_exactly_the_stimuli_whose_clicks_fell_on_one_point(tmp_path):
    """The per-stimulus rows (one groupby, not one filter of every click per stimulus)."""
    import pandas as pd

    from attneave.analysis.analyze import analyze
    from attneave.analysis.report.html import _stimulus_rows
    from attneave.stimuli.stimulus_set import read_stimulus_set

    shapes = _shapes(3)
    write_stimulus_set(tmp_path / "set", shapes, size=(400, 400))
    stimset = read_stimulus_set(tmp_path / "set")
    rows = []
    for p in range(4):
        for k in range(5):
            rows.append((f"p{p}", "rf_0", *shapes["rf_0"][0]))  # one point, every time
            rows.append((f"p{p}", "rf_1", *shapes["rf_1"][(37 * (5 * p + k)) % 200]))  # spread
            rows.append((f"p{p}", "rf_2", *shapes["rf_2"][(p + k) % 2 * 100]))  # two points
    clicks = pd.DataFrame(rows, columns=["participant", "stimulus_id", "x", "y"])
    a = analyze(clicks, stimset, n=40, permutations=9, group_simulations=9, grid=64, mixed=False, quiet=True)
    table, single = _stimulus_rows(a, {})
    assert single == ["rf_0"]
    marked = [r[0] for r in table if str(r[-1]).endswith(" *")]
    assert marked == ["rf_0"]


def test_a_large_table_lookup_in_runs_equals_the_exact_moments_and_each_cell_alone():
    """A lookup of many cells runs in runs of _RUN cells over slopes that span several blocks and
    the bound: each cell has the value it has alone, within the interpolation's error of the exact
    log-sum-exp, mean and variance, and is linear beyond the bound."""
    import scipy.special

    from attneave.analysis.models.cumulants import _RUN

    rng = np.random.default_rng(7)
    Z = standardize(rng.gamma(1.0, size=(30, 50)))
    tab = CumulantTable(Z)
    m = 3 * _RUN + 1001
    s, b = rng.integers(0, 30, m), rng.uniform(-3, 3, m)
    K, E, V, D = tab(s, b, dV=True)
    for q in rng.choice(m, 20, replace=False):
        alone = tab(s[q:q + 1], b[q:q + 1], dV=True)
        assert [a[0] for a in alone] == [K[q], E[q], V[q], D[q]]
    x = b[:, None] * Z[s]
    p = scipy.special.softmax(x, axis=1)
    mean = (p * Z[s]).sum(axis=1)
    assert np.abs(K - scipy.special.logsumexp(x, axis=1)).max() < 1e-8
    assert np.abs(E - mean).max() < 1e-7
    assert np.abs(V - (p * (Z[s] - mean[:, None]) ** 2).sum(axis=1)).max() < 1e-6
    # V' is the derivative of the interpolated V
    e = 1e-6
    np.testing.assert_allclose(D, (tab(s, b + e)[2] - tab(s, b - e)[2]) / (2 * e), atol=1e-5)
    beyond = tab(s[:5], np.full(5, tab.bound + 2.0), dV=True)
    at = tab(s[:5], np.full(5, tab.bound))
    np.testing.assert_allclose(beyond[0], at[0] + 2.0 * at[1], rtol=1e-12)
    assert (beyond[2] == 0).all() and (beyond[3] == 0).all()


def test_mapping_many_stimuli_at_once_equals_mapping_each_alone(tmp_path):
    import pandas as pd

    from attneave.analysis.clicks.mapping import map_clicks, predict
    from attneave.analysis.simulate.observers import simulate
    from attneave.stimuli.stimulus_set import read_stimulus_set

    write_stimulus_set(tmp_path / "set", _shapes(70), size=(400, 400))
    pred = predict(read_stimulus_set(tmp_path / "set"), n=40)
    clicks, _ = simulate(pred, 3, 2, 1.0, seed=1, noise=2.0)
    clicks.loc[0, "x"] = 5000.0  # one outside its image
    whole = map_clicks(clicks, pred)
    assert whole.loc[0, "reason"] == "outside_image"
    for sid in ("rf_0", "rf_33", "rf_69"):
        alone = map_clicks(clicks[clicks["stimulus_id"] == sid], {sid: pred[sid]})
        part = whole[whole["stimulus_id"] == sid]
        pd.testing.assert_frame_equal(alone.reset_index(drop=True), part.reset_index(drop=True))


def test_ordered_map_keeps_order_and_cancels_what_has_not_started_when_the_caller_stops():
    """The threaded passes (Monte Carlo chunks, choice-model blocks) run through ordered_map: a stop
    (here an exception in the consumer, as KeyboardInterrupt or the SIGTERM handler raises) must not
    wait for the remaining items."""
    import threading
    import time

    from attneave.analysis.threads import MAX_THREADS, ordered_map

    assert list(ordered_map(lambda i: i * 3, 50)) == [3 * i for i in range(50)]
    started = []
    lock = threading.Lock()

    def slow(i):
        with lock:
            started.append(i)
        time.sleep(0.05)
        return i

    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        for i in ordered_map(slow, 200):
            if i == 2:
                raise KeyboardInterrupt
    assert time.perf_counter() - t0 < 2.0  # 200 items would take 5 s on two threads
    assert len(started) <= 3 + 2 * MAX_THREADS
