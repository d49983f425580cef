"""report.html's words and Figure 1 on a real analysis: what a reader must be told, said in the text."""

import numpy as np
import pytest

from attneave.analysis.analyze import analyze
from attneave.analysis.report.html import render
from attneave.analysis.report.plots import all_figures, group_figure


@pytest.fixture(scope="module")
def analysis(tmp_path_factory):
    import pandas as pd

    from attneave.analysis.clicks.mapping import predict
    from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set

    d = tmp_path_factory.mktemp("text")
    rng = np.random.default_rng(5)
    shapes = {}
    for i in range(4):
        k = 5 + i
        th = 2 * np.pi * (np.arange(k) + rng.uniform(-0.3, 0.3, k)) / k
        r = 140 * rng.uniform(0.5, 1.0, k)
        shapes[f"shape_{i}"] = np.c_[256 + r * np.cos(th), 256 + r * np.sin(th)]
    shapes["practice_item"] = shapes["shape_0"][::-1] * 0.8 + 40
    write_stimulus_set(d / "set", shapes)
    ss = read_stimulus_set(d / "set")
    pred = predict(ss)
    rows = []
    for p in ("ana", "bo", "cy", "dee"):  # ids that are not positions
        for sid in ("shape_0", "shape_1", "shape_2", "shape_3"):  # nobody clicked the practice item
            pr = pred[sid]
            for j in rng.choice(pr.n, 6, p=np.exp(pr.z["surprisal"]) / np.exp(pr.z["surprisal"]).sum()):
                x, y = pr.contour.point_at([j / pr.n])[0]
                rows.append(dict(participant=p, stimulus_id=sid, x=x, y=y))
    return analyze(pd.DataFrame(rows), ss, predictions=pred, group_simulations=0, permutations=0)


def _page(a, **changes):
    s = dict(a.summary, version="x", date="d")
    for k, v in changes.items():
        s[k] = v
    return render(a, s, [])


def test_a_variance_at_its_boundary_is_said_in_words(analysis):
    m = dict(analysis.summary["mixed"], beta=0.5, ci_low=0.4, ci_high=0.6, df=3, sd_participant=0.0,
             sd_stimulus=0.31)
    page = _page(analysis, mixed=m)
    assert "SD = 0.00 across participants" in page
    assert "slope across participants was estimated at zero, the boundary of its range" in page
    assert "across stimuli was estimated at zero" not in page
    both = _page(analysis, mixed=dict(m, sd_stimulus=0.0))
    assert "across participants and across stimuli was estimated at zero" in both


def test_a_rival_that_fits_better_is_named_in_the_text(analysis):
    models = {k: dict(v) for k, v in analysis.summary["models"].items()}
    models["surprisal"]["aic"] = 1000.0
    models["extremum_proximity"] = dict(models.get("extremum_proximity", {}), aic=425.2)
    page = _page(analysis, models=models)
    assert "Surprisal was not the best predictor" in page
    assert "nearness to a curvature extremum (AIC lower by 574.8)" in page
    models["extremum_proximity"]["aic"] = 2000.0
    for k in models:
        if k != "surprisal":
            models[k]["aic"] = 2000.0
    assert "surprisal fitted the clicks best" in _page(analysis, models=models)


def test_figure_1_names_participants_by_id(analysis):
    fig = group_figure(analysis)
    labels = [t.get_text() for t in fig.axes[0].get_xticklabels()]
    pp = analysis.per_participant
    assert labels == list(pp["participant"].to_numpy()[np.argsort(pp["mean_z"].to_numpy())])
    assert sorted(labels) == ["ana", "bo", "cy", "dee"]


def test_an_unclicked_stimulus_gets_no_panel_but_is_named(analysis):
    figs = all_figures(analysis)
    captions = [cap for stem, cap, *_ in figs if stem.startswith("stimuli_")]
    assert len(captions) == 1  # four clicked stimuli: one page of six panels
    shown = captions[0].split(". For each stimulus")[0]
    assert "practice_item" not in shown and "shape_3" in shown
    assert "Not drawn: 1 stimulus without any click (e.g. practice items): practice_item." in captions[0]
