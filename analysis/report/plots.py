"""Figures of an analysis (PNG bytes; matplotlib's object API, no pyplot state).

* :func:`stimulus_page`: for each stimulus, the image (when its file exists)
  with the contour as participants saw it -- whole, or only its fragments,
  dots or polygon (:mod:`attneave.analysis.clicks.drawn`), the rest of the
  contour thin and grey -- coloured by surprisal (yellow high, purple low),
  the predicted peaks, the used clicks (black), clicks far from every drawn
  part (orange triangles) and the other excluded ones that have coordinates
  (red crosses); beside it, the click density along the contour and the
  standardised surprisal z against arc position t (drawn stretches shaded).
  Stimuli that nobody clicked (practice items, say) get no panel.
* :func:`group_figure`: each participant's effect (mean z at their clicks),
  labelled with their ids, with the group mean and its interval; the click
  rate against z (observed and predicted by the fitted model, relative to
  uniform clicking); and the log-likelihood gain of each model over uniform
  clicking. Legends sit outside the data.

Images are drawn in image pixels with y down (``extent`` from -0.5 to
W - 0.5, pixel centres at integers), as the clicks are.
"""

from __future__ import annotations

import io

import numpy as np

from attneave.analysis.clicks.drawn import describe

__all__ = ["stimulus_page", "group_figure", "all_figures", "to_png", "to_svg"]


def _figure(w, h, dpi=80, layout=None):
    from matplotlib.figure import Figure

    # fixed margins rather than constrained layout, which costs half the drawing time
    return Figure(figsize=(w, h), dpi=dpi, layout=layout)


def _click_groups(analysis):
    """Per stimulus: used clicks (x, y, t) and excluded ones with coordinates (x, y)."""
    c = analysis.clicks
    sid = c["stimulus_id"].to_numpy(dtype=object)
    exc = c["excluded"].to_numpy(dtype=bool)
    off = (c["reason"] == "off_drawn_part").to_numpy()
    xi, yi, t = (c[k].to_numpy(dtype=float) for k in ("x_image", "y_image", "t"))
    has_xy = np.isfinite(xi)
    out = {}
    order = np.argsort(sid.astype(str), kind="stable")
    keys, starts = np.unique(sid[order].astype(str), return_index=True)
    bounds = list(starts[1:]) + [len(order)]
    for k, a, b in zip(keys, starts, bounds):
        rows = order[a:b]
        u = rows[~exc[rows]]
        bad = rows[exc[rows] & has_xy[rows] & ~off[rows]]
        gap = rows[off[rows]]
        out[k] = dict(x=xi[u], y=yi[u], t=t[u], bad_x=xi[bad], bad_y=yi[bad], off_x=xi[gap], off_y=yi[gap],
                      n_rows=len(rows))
    return out


def to_png(fig):
    """Render a figure to PNG bytes (no timestamp, so reruns give the same bytes)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None})
    return buf.getvalue()


def to_svg(fig):
    """Render a figure to SVG bytes (no date, fixed ids, so reruns give the same bytes)."""
    import matplotlib

    buf = io.BytesIO()
    with matplotlib.rc_context({"svg.hashsalt": "attneave"}):
        fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": None})
    return buf.getvalue()


def _read_image(path):
    if path is None:
        return None
    try:
        import cv2

        im = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    except Exception:  # an unreadable image only loses the background of a figure
        return None
    return im


def _norm(u):
    from matplotlib.colors import Normalize

    return Normalize(float(np.min(u)), float(np.max(u)) if np.ptp(u) > 0 else float(np.min(u)) + 1.0)


def _shown_points(drawn, n):
    """Which of the n points (and the segment that starts at each) lie on a drawn fragment."""
    t = np.arange(n) / n
    if drawn.mode != "fragments":
        return np.zeros(n, bool)
    out = np.zeros(n, bool)
    for a, b in drawn.spans:
        # the segment from point i to i+1 is drawn when its middle lies in the span (modulo 1)
        mid = np.mod(t + 0.5 / n - a, 1.0)
        out |= mid <= (b - a)
    return out


def _nearest_points(drawn, n):
    """The points of the n nearest to each dot or polygon corner (by arc position)."""
    from attneave.analysis.models.choice import point_index

    return np.unique(point_index(np.asarray(drawn.t), n))


def _shape_panel(ax, analysis, sid, groups):
    from matplotlib.collections import LineCollection

    pr = analysis.predictions[sid]
    W, H = pr.width, pr.height
    im = _read_image(analysis.stimset.images.get(sid)) if analysis.stimset is not None else None
    if im is not None:
        ax.imshow(im, cmap="gray", vmin=0, vmax=255, extent=(-0.5, W - 0.5, H - 0.5, -0.5), alpha=0.35,
                  interpolation="nearest")
    p = pr.result.contour.points
    u = pr.predictors["surprisal"]
    seg = np.stack([p, np.roll(p, -1, axis=0)], axis=1)
    drawn = getattr(pr, "drawn", None)
    shown = np.ones(len(p), bool) if drawn is None else _shown_points(drawn, pr.n)
    if drawn is not None:  # what was not drawn: thin and grey, so that the gaps read as gaps
        ax.add_collection(LineCollection(seg, colors="0.75", linewidths=0.8, linestyles=(0, (2, 2))))
    colour = 0.5 * (u + np.roll(u, -1))
    norm = _norm(u)
    if drawn is None or drawn.mode == "fragments":
        lc = LineCollection(seg[shown], cmap="viridis", norm=norm, linewidths=2.5)
        lc.set_array(colour[shown])
        ax.add_collection(lc)
    else:
        if drawn.mode == "polygon":
            ax.plot(drawn.polylines[0][:, 0], drawn.polylines[0][:, 1], "-", color="0.35", lw=1.5)
        k = _nearest_points(drawn, pr.n)
        ax.scatter(p[k, 0], p[k, 1], c=u[k], cmap="viridis", norm=norm, s=36, zorder=3, edgecolors="0.3")
    peaks = np.asarray(pr.result.peaks, int)
    peaks = peaks[shown[peaks]] if len(peaks) else peaks
    if len(peaks):
        ax.plot(p[peaks, 0], p[peaks, 1], "o", mfc="none", mec="tab:red", ms=7, mew=1.2)
    g = groups.get(sid, dict(x=[], y=[], t=[], bad_x=[], bad_y=[], off_x=[], off_y=[]))
    # clicks as pixels in the SVG too: thousands of markers would make it huge and slow
    ax.plot(g["x"], g["y"], ".", color="k", ms=3, alpha=0.6, rasterized=True)
    ax.plot(g["bad_x"], g["bad_y"], "x", color="tab:red", ms=4, rasterized=True)
    ax.plot(g["off_x"], g["off_y"], "^", color="tab:orange", mec="k", mew=0.5, ms=6, rasterized=True)
    ax.set_xlim(-0.5, W - 0.5)
    ax.set_ylim(H - 0.5, -0.5)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    off = f", {len(g['off_x'])} off drawn part" if len(g["off_x"]) else ""
    what = "" if drawn is None else f"{describe(drawn)}; "
    ax.set_title(f"{sid}\n({what}{len(g['x'])} used clicks{off})", fontsize=9)


def _profile_panel(ax, analysis, i, sid, groups):
    prof = analysis.profiles
    row = analysis.per_stimulus.iloc[i]
    t = prof["t"]
    ax.plot(t, prof["z"][i], color="tab:orange", lw=1.4)
    ax.set_xlim(0, 1)
    ax.set_xlabel("arc position t (fraction of perimeter)", fontsize=9)
    ax.set_ylabel("surprisal z", fontsize=9, color="tab:orange")
    ax.tick_params(labelsize=8)
    ax2 = ax.twinx()
    d = prof["density"][i]
    if np.isfinite(d).all():
        ax2.plot(t, d, color="tab:blue", lw=1.4)
        ax2.set_ylim(bottom=0)
    ax2.set_ylabel("click density (1 = uniform)", fontsize=9, color="tab:blue")
    ax2.tick_params(labelsize=8)
    tc = np.asarray(groups.get(sid, {}).get("t", []))
    lo = ax.get_ylim()[0]
    ax.plot(tc, np.full(len(tc), lo), "|", color="k", ms=7, alpha=0.4, rasterized=True)
    # no legend over the curves: the axis labels carry the colours, the caption says the rest
    drawn = getattr(analysis.predictions[sid], "drawn", None)
    for a, b in (drawn.spans if drawn is not None else []):
        for a0, b0 in ((a, b), (a - 1, b - 1), (a + 1, b + 1)):  # a fragment across t = 0 wraps
            if b0 > 0 and a0 < 1:
                ax.axvspan(max(a0, 0), min(b0, 1), color="0.85", zorder=0, lw=0)
    rho, p = row["spearman_rho"], row["spearman_p"]
    txt = f"Spearman rho = {rho:.2f}, p = {p:.2g}" if np.isfinite(rho) else "Spearman rho: n/a"
    ax.set_title(txt, fontsize=9)


def stimulus_page(analysis, ids, per_row=2, groups=None):
    """One page of stimuli: shape with clicks, and density/surprisal profile."""
    groups = _click_groups(analysis) if groups is None else groups
    rows = int(np.ceil(len(ids) / per_row))
    height = 3.6 * rows
    fig = _figure(4.4 * 2 * per_row, height, dpi=100)
    # margins in inches, whatever the number of rows
    axes = fig.subplots(rows, 2 * per_row, squeeze=False, width_ratios=[1, 1.3] * per_row,
                        gridspec_kw=dict(left=0.03, right=0.96, bottom=0.55 / height, top=1 - 0.35 / height,
                                         wspace=0.5, hspace=1.0 / 3.6))
    index = {s: i for i, s in enumerate(analysis.profiles["ids"])}
    for k in range(rows * per_row):
        a_shape, a_prof = axes[k // per_row, 2 * (k % per_row)], axes[k // per_row, 2 * (k % per_row) + 1]
        if k >= len(ids):
            a_shape.set_axis_off()
            a_prof.set_axis_off()
            continue
        sid = ids[k]
        _shape_panel(a_shape, analysis, sid, groups)
        _profile_panel(a_prof, analysis, index[sid], sid, groups)
    return fig


def _calibration(analysis, bins=8):
    """Relative click rate per z bin: observed and predicted at beta_hat."""
    ids = analysis.profiles["ids"]
    Z = np.stack([analysis.predictions[s].z["surprisal"] for s in ids])
    c = analysis.clicks
    used = c[~c["excluded"]]
    sidx = used["stimulus_id"].map({s: i for i, s in enumerate(ids)}).to_numpy().astype(int)
    if len(sidx) == 0:
        return None
    M = np.bincount(sidx, minlength=len(ids)).astype(float)
    zc = Z[M > 0].ravel()
    if np.ptp(zc) == 0:
        return None
    # quantile bins, none narrower than a sixteenth of the range; tied z (a polygon: most points share a
    # low z, a few corners carry the rest) leaves few such bins, and equal widths then show the rise at
    # high z instead of every bin at one z
    lo, hi = zc.min(), zc.max()
    edges = [lo]
    for e in np.quantile(zc, np.linspace(0, 1, bins + 1))[1:-1]:
        if e - edges[-1] >= (hi - lo) / (2 * bins) and hi - e >= (hi - lo) / (2 * bins):
            edges.append(e)
    edges = np.array(edges + [hi])
    if len(edges) - 1 < bins // 2:
        edges = np.linspace(lo, hi, bins + 1)
    nb = len(edges) - 1
    which = np.clip(np.searchsorted(edges, Z, side="right") - 1, 0, nb - 1)
    n = Z.shape[1]
    beta = analysis.summary["beta_hat"] or 0.0
    w = np.exp(beta * Z - (beta * Z).max(axis=1, keepdims=True))
    p = w / w.sum(axis=1, keepdims=True)
    N = M.sum()
    uni = np.array([(M[:, None] * (which == b)).sum() / n / N for b in range(nb)])
    pred = np.array([(M[:, None] * p * (which == b)).sum() / N for b in range(nb)])
    zcl = Z[sidx, used["point"].to_numpy().astype(int)]
    wc = np.clip(np.searchsorted(edges, zcl, side="right") - 1, 0, nb - 1)
    obs = np.bincount(wc, minlength=nb) / N
    filled = uni > 0  # equal-width bins may hold no point
    centre = np.array([Z[(which == b) & (M[:, None] > 0)].mean() if filled[b] else np.nan for b in range(nb)])
    return centre[filled], obs[filled] / uni[filled], pred[filled] / uni[filled]


def group_figure(analysis):
    """Participants' effects, click rate against z, and model comparison."""
    fig = _figure(15, 4.6, layout="constrained")
    ax1, ax2, ax3 = fig.subplots(1, 3)
    pp = analysis.per_participant
    g = analysis.summary["group"]
    v = pp["mean_z"].to_numpy()
    order = np.argsort(np.where(np.isfinite(v), v, -np.inf))
    ax1.axhline(0, color="0.5", lw=1)
    ax1.plot(np.arange(len(v)), v[order], "o", color="tab:blue", ms=4)
    if g["mean"] is not None:
        ax1.axhline(g["mean"], color="tab:red", lw=1.5)
        if g["ci_low"] is not None:
            ax1.axhspan(g["ci_low"], g["ci_high"], color="tab:red", alpha=0.15)
    # each participant by their id, not by a position; with many, every k-th id, so that none overlap
    ids = pp["participant"].astype(str).to_numpy()[order] if "participant" in pp.columns else np.arange(len(v))
    step = max(1, int(np.ceil(len(v) / 40)))
    ax1.set_xticks(np.arange(0, len(v), step), [str(k) for k in ids[::step]], rotation=90,
                   fontsize=7 if len(v) > 15 else 8)
    ax1.set_xlim(-0.7, max(len(v) - 0.3, 0.7))
    ax1.set_xlabel("participant (sorted by mean z)" + (f", every {step}th id" if step > 1 else ""))
    ax1.set_ylabel("mean z at clicks")
    p = g["p_value"]
    ax1.set_title(f"group: t = {g['statistic'] if g['statistic'] is None else round(g['statistic'], 2)}, "
                  f"Monte Carlo p = {p if p is None else f'{p:.2g}'} (one-sided, R = {g.get('simulations')})",
                  fontsize=10)
    cal = _calibration(analysis)
    if cal is not None:
        centre, obs, pred = cal
        from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

        o = np.argsort(centre)
        ax2.axhline(1, color="0.5", lw=1, label="uniform clicking")
        ax2.plot(centre[o], obs[o], "o", color="k", label="observed")
        ax2.plot(centre[o], pred[o], "s--", color="tab:red", ms=4, lw=1,
                 label=f"choice model, beta = {analysis.summary['beta_hat']:.2f}")
        ax2.set_yscale("log")
        ax2.yaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        ax2.yaxis.set_major_formatter(ScalarFormatter())
        # ticks at 1, 2, 5 x 10^k with plain labels, not two bare powers of ten
        ax2.yaxis.set_minor_formatter(NullFormatter())
        # below the axes, not over the points
        ax2.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False)
    ax2.set_xlabel("z (standardised surprisal), bin mean")
    ax2.set_ylabel("click rate / uniform rate")
    ax2.set_title("clicks against predicted information", fontsize=10)
    m = analysis.models
    ll0 = float(m.loc[m["model"] == "uniform", "loglik"].iloc[0])
    gain = m["loglik"].to_numpy() - ll0
    from attneave.analysis.report.wording import predictor_name

    ax3.barh([predictor_name(k).replace(" (eq. 5; tested)", "") for k in m["model"]], gain,
             color=["tab:red" if k else "tab:gray" for k in m["tested"]])
    ax3.set_xlabel("log-likelihood gain over uniform (nats)")
    ax3.set_title("model comparison", fontsize=10)
    return fig


GROUP_CAPTION = ("Left: each participant's mean standardised surprisal z at their used clicks (dots, sorted; 0 under "
                 "uniform clicking; labelled with the participants' ids), with the group mean (red line) and its {level:g}% t interval (band). Middle: the "
                 "click rate in bins of z relative to uniform clicking (log scale): observed (dots) and predicted by "
                 "the pooled choice model (squares), legend below. Right: log-likelihood gain over uniform clicking of the choice "
                 "model with each predictor alone (red: surprisal, the model under test).")
STIMULUS_CAPTION = ("Stimuli {ids}. For each stimulus, left: the contour as shown to participants, coloured by "
                    "surprisal (yellow high, purple low), predicted peaks (red), used clicks (black dots) and excluded "
                    "clicks with coordinates (red crosses){drawn}; right: standardised surprisal z (orange, left axis) "
                    "and the click density (blue, right axis, 1 = uniform) along the contour from its first point, "
                    "with the used clicks as ticks{spans}; the title gives Spearman's rho between them and its "
                    "circular-shift p.{unclicked}")
DRAWN_CAPTION = ("; where only fragments, dots or a polygon were shown, the rest of the contour is a thin grey dashed "
                 "line and clicks far from every drawn part are orange triangles")


def all_figures(analysis, per_page=6):
    """Every figure of the report, group figure first.

    Returns
    -------
    list of (stem, caption, PNG bytes, SVG bytes)
    """
    fig = group_figure(analysis)
    # the band is the group test's interval, at the analysis's confidence level
    level = 100 * analysis.summary.get("params", {}).get("level", 0.95)
    out = [("group", GROUP_CAPTION.format(level=level), to_png(fig), to_svg(fig))]
    groups = _click_groups(analysis)
    # a stimulus without a single click row (a practice item, whose clicks the page keeps apart) would be
    # an empty panel: it is named in the caption instead
    every = [str(s) for s in analysis.profiles["ids"]]
    ids = [s for s in every if groups.get(s, {}).get("n_rows", 0) > 0]
    missing = [s for s in every if s not in set(ids)]
    unclicked = "" if not missing else (
        f" Not drawn: {len(missing)} stimul{'us' if len(missing) == 1 else 'i'} without any click (e.g. practice "
        f"items): {', '.join(missing[:8])}{', ...' if len(missing) > 8 else ''}.")
    for k in range(0, len(ids), per_page):
        page = ids[k:k + per_page]
        fig = stimulus_page(analysis, page, groups=groups)
        drawn = any(getattr(analysis.predictions[s], "drawn", None) is not None for s in page)
        cap = STIMULUS_CAPTION.format(ids=", ".join(page), drawn=DRAWN_CAPTION if drawn else "",
                                      spans="; grey bands: the stretches of contour that were drawn" if drawn else "",
                                      unclicked=unclicked if k == 0 else "")
        out.append((f"stimuli_{k // per_page + 1:03d}", cap, to_png(fig), to_svg(fig)))
    return out
