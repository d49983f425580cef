"""report.html: the analysis written as a methods-and-results section.

One self-contained page: the software and date, the design and exclusions,
the prediction and every parameter, the models, and the results in APA style
(numbers to sensible precision, p as ``p = .023`` or ``p < .001``), the
figures with captions that say what they show (each also as SVG beside the
PNG), and compact tables. Estimates that cannot be trusted are flagged rather
than printed as numbers: a per-stimulus or per-participant beta at the search
bound or with an infinite standard error, and Spearman's rho on a stimulus
whose clicks all fall on one point.
"""

from __future__ import annotations

import base64
import html
import math

__all__ = ["num", "pval", "render"]


def num(v, digits=2):
    """A number to `digits` decimals; n/a for None/NaN/inf.

    Examples
    --------
    >>> num(0.123456), num(1234.5), num(-0.0001), num(None)
    ('0.12', '1234.50', '-0.00', 'n/a')
    """
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "n/a"
    if isinstance(v, bool) or isinstance(v, int):
        return str(v)
    return f"{float(v):.{digits}f}"


def pval(p, prefix=True):
    """A p-value in APA style: no leading zero, ``< .001`` below that.

    Examples
    --------
    >>> pval(0.0234), pval(0.00002), pval(0.5), pval(None), pval(0.0234, prefix=False)
    ('p = .023', 'p < .001', 'p = .500', 'p = n/a', '.023')
    """
    if p is None or not math.isfinite(p):
        text = "= n/a"
    elif p < 0.001:
        text = "< .001"
    else:
        text = "= " + f"{p:.3f}".lstrip("0")
    return "p " + text if prefix else text.removeprefix("= ")


def t_text(test, digits=2):
    """A group or items test's t, or why it has none: with no spread across units (every unit's
    mean z the same, as when every click is on its contour's top point) t is infinite (null in JSON).

    Examples
    --------
    >>> t_text(dict(statistic=2.5, n=4, sd=1.0, mean=1.25)), t_text(dict(statistic=None, n=4, sd=0.0, mean=6.9))
    ('2.50', 'n/a (no spread: every mean z is 6.90)')
    """
    t, sd, mean = test.get("statistic"), test.get("sd"), test.get("mean")
    if t is None and (test.get("n") or 0) >= 2 and sd is not None and mean is not None \
            and sd <= 1e-12 * max(1.0, abs(mean)):
        return f"n/a (no spread: every mean z is {num(mean, digits)})"
    return num(t, digits)


def _count(k, one, many=None):
    """'1 participant', '3 participants'."""
    return f"{k} {one if k == 1 else (many or one + 's')}"


def _t_df(test):
    """'t(df)', or 't' where a test of fewer than two units has no degrees of freedom."""
    return f"t({test['df']})" if test.get("df") is not None else "t"


def _pct(v):
    return "n/a" if v is None else f"{100 * v:.1f}%"


def _files(v):
    """The click file(s) as given: one path, or the first few of a list and how many in all."""
    if not isinstance(v, list):
        return str(v)
    shown = ", ".join(str(p) for p in v[:3])
    return shown + (f" and {len(v) - 3} more ({len(v)} files)" if len(v) > 3 else "")


def _table(header, rows, cls=""):
    esc = html.escape
    head = "".join(f"<th>{esc(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{esc(str(c))}</td>" for c in r) + "</tr>" for r in rows)
    return f'<table class="{cls}"><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>'


def _flagged_beta(beta, se, at_bound):
    if at_bound:
        return "at bound (not estimable)"
    if se is None or not math.isfinite(se) or beta is None or not math.isfinite(beta):
        return "n/a (infinite SE)"
    return f"{num(beta)} ({num(se)})"


def _stimulus_rows(a):
    ps = a.per_stimulus
    rows, notes = [], []
    for r in ps.itertuples():
        rho = "n/a" if not math.isfinite(r.spearman_rho) else f"{num(r.spearman_rho)} ({pval(r.spearman_p, False)})"
        if r.n_used > 0 and not r.constant_prediction:
            pts = a.clicks.loc[(a.clicks["stimulus_id"] == r.stimulus_id) & ~a.clicks["excluded"], "point"]
            if pts.nunique() == 1:
                rho += " *"
                notes.append(r.stimulus_id)
        # a stimulus nobody clicked has no estimate at all, not one with an infinite SE
        beta = "n/a (no used clicks)" if r.n_used == 0 else _flagged_beta(r.beta_hat, r.beta_se, r.beta_at_bound)
        rows.append([r.stimulus_id, r.n_used, beta, num(r.mean_z),
                     _pct(r.top_share) if math.isfinite(r.top_share) else "n/a", rho])
    return rows, notes


def _ci(s):
    """'95% CI', at the confidence level the analysis used (``params.level``)."""
    return f"{100 * s['params'].get('level', 0.95):g}% CI"


def _p(v):
    """:func:`pval` for HTML text: its '<' escaped."""
    return html.escape(pval(v))


def _results(s):
    g, it, m, e = s["group"], s["by_stimulus"], s.get("mixed") or {}, s["effect"]
    out = []
    out.append(
        f"Of {s['n_clicks']} clicks, {s['n_used']} were used ({s['n_excluded']} excluded; reasons below), from "
        f"{_count(s['n_participants_used'], 'participant')} on {s['n_stimuli_clicked']} of "
        f"{_count(s['n_stimuli'], 'stimulus', 'stimuli')}.")
    out.append(
        f"{_pct(e['top_share'])} of the used clicks fell on the top {100 * e['fraction']:.0f}% of their contour's "
        f"points by surprisal, against {_pct(e['chance_share'])} expected by chance (lift = {num(e['lift'])}).")
    if m.get("beta") is not None:
        out.append(
            f"In the mixed conditional logit with crossed random slopes, the mean weight of standardised surprisal "
            f"was &beta; = {num(m['beta'])}, {_ci(s)} [{num(m['ci_low'])}, {num(m['ci_high'])}] (t quantiles, df = "
            f"{m['df']}), with SD = {num(m['sd_participant'])} across participants and SD = {num(m['sd_stimulus'])} "
            f"across stimuli.")
    out.append(
        f"The group test across participants gave {_t_df(g)} = {t_text(g)}, {_p(g['p_value'])} "
        f"(one-sided, Monte Carlo null of uniform clicking, R = {g['simulations']}), d<sub>z</sub> = "
        f"{num(g['effect_size'])}; the items test across stimuli {_t_df(it)} = {t_text(it)}, "
        f"{_p(it['p_value'])}.")
    if s["beta_at_bound"]:  # the bound and an interval around it are no estimate: flagged, not printed
        out.append(f"The pooled fit (clicks treated as independent) reached the "
                   f"{'upper' if s['beta_hat'] > 0 else 'lower'} bound of its search: &beta; is not estimable "
                   f"(near-separation).")
    else:
        out.append(
            f"The pooled fit (clicks treated as independent) gave &beta; = {num(s['beta_hat'])}, {_ci(s)} "
            f"[{num(s['beta_ci'][0])}, {num(s['beta_ci'][1])}].")
    sp = s["spearman"]
    out.append(f"Click density correlated with surprisal along the contours with mean Spearman rho = "
               f"{num(sp['mean_rho'])}, {_p(sp['p_value'])} (circular shifts), over {sp['n_stimuli']} stimuli.")
    return " ".join(out)


def render(analysis, summary, figures):
    """The page. `figures`: list of (stem, caption, png bytes, svg file name)."""
    esc = html.escape
    s, p = summary, summary["params"]
    excl = [[k.replace("_", " "), v] for k, v in s["exclusions"].items()]
    pred_rows = [[k, "at bound" if v.get("at_bound") else num(v["coef"]),
                  "n/a" if v.get("at_bound") else f"[{num(v['ci_low'])}, {num(v['ci_high'])}]",
                  "at bound" if v.get("at_bound") else pval(v["lr_p"], False)] for k, v in s["predictors"].items()]
    models = [[r.model + (" (tested)" if r.tested else ""),
               "at bound" if r.at_bound else num(r.beta_hat), num(r.loglik, 1), num(r.delta_aic, 1)]
              for r in analysis.models.itertuples()]
    stim_rows, single = _stimulus_rows(analysis)
    flagged = int(analysis.per_stimulus["beta_at_bound"].sum())
    params = [[k, str(v if not isinstance(v, dict) else v.get("rule", v))] for k, v in sorted(p.items())]
    figs = "\n".join(
        f'<figure><img alt="{esc(stem)}" src="data:image/png;base64,{base64.b64encode(png).decode("ascii")}">'
        f'<figcaption><b>Figure {i + 1}.</b> {esc(cap)} (<a href="figures/{esc(svg)}">SVG</a>)</figcaption></figure>'
        for i, (stem, cap, png, svg) in enumerate(figures))
    warn = "".join(f"<p class=warn>{esc(w)}</p>" for w in s.get("warnings", []))
    left_out = "; ".join(f"{k}: {v}" for k, v in s.get("models_left_out", {}).items())
    methods = (
        f"Each click was mapped to the nearest point of its stimulus's contour (excluded beyond "
        f"{esc(p['tolerance']['rule'])}). The prediction is the surprisal of eq. 5 of the seed paper "
        f"({esc(str(p['model']))} form, A' = {p.get('A')}, b = {p.get('b')}) at n = {p['n']} equally spaced points "
        f"per contour, with arc length in unit <code>{esc(str(s['length_unit']))}</code>, standardised per stimulus "
        f"(z: mean 0, SD 1). Clicks were modelled as a discrete choice among the n points, p(j) &prop; "
        f"exp(&beta; z<sub>j</sub>) (a conditional logit), fitted pooled, jointly with the predictors "
        f"{esc(', '.join(s['predictors']))}, and as a mixed model with crossed random slopes for participants and "
        f"stimuli (Laplace approximation). The group test compares per-participant mean z with its Monte Carlo "
        f"null under uniform clicking (R = {p['group_simulations']}); the items test does the same across stimuli. "
        f"The portable effect size is the share of clicks on the top {100 * s['effect']['fraction']:.0f}% of points. "
        f"The von Mises form of surprisal is not a rival: standardised, it equals the paper's form."
        + (f" Left out as identical to another predictor: {esc(left_out)}." if left_out else ""))
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width">
<title>attneave analysis</title>
<style>
body {{ font-family: Georgia, serif; margin: 2em auto; max-width: 1100px; padding: 0 1em; line-height: 1.45; }}
h1, h2 {{ font-family: sans-serif; }}
table {{ border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 90%; max-width: 100%; }}
th, td {{ border-bottom: 1px solid #ccc; padding: 3px 10px; text-align: left; overflow-wrap: anywhere; }}
thead th {{ border-bottom: 2px solid #333; }}
img {{ max-width: 100%; height: auto; }} figure {{ margin: 1em 0 2em; }}
figcaption {{ font-size: 90%; }} .warn {{ color: #a00; }} code {{ font-size: 90%; }}
.scroll {{ max-height: 40em; overflow-y: auto; }}
</style></head><body>
<h1>Clicks against predicted information along contours</h1>
<p>attneave {esc(str(s.get('version')))}, run {esc(str(s.get('date')))}; clicks: <code>{esc(_files((s.get('inputs') or {}).get('clicks', 'n/a')))}</code>,
stimuli: <code>{esc(str((s.get('inputs') or {}).get('stimuli', 'n/a')))}</code>.</p>
{warn}
<h2>Method</h2>
<p>{methods}</p>
<h3>Exclusions</h3>
{_table(["reason", "clicks"], excl)}
<h3>Parameters</h3>
{_table(["parameter", "value"], params)}
<h2>Results</h2>
<p>{_results(s)}</p>
<h3>Predictors fitted jointly</h3>
{_table(["predictor", "coefficient", _ci(s), "LR test p (without it)"], pred_rows)}
<h3>Each predictor alone (models.csv)</h3>
{_table(["model", "beta", "log-likelihood", "delta AIC"], models)}
<h2>Figures</h2>
{figs or '<p>(figures not drawn)</p>'}
<h2>Per stimulus</h2>
<p>beta (SE) from the stimulus's clicks alone; {flagged} fit(s) at the search bound are flagged, not estimated.
{'* every used click on this stimulus fell on one point: its Spearman correlation ranks a single spike and is not interpretable (' + esc(', '.join(single)) + ').' if single else ''}</p>
<div class="scroll">{_table(["stimulus", "used clicks", "beta (SE)", "mean z", "top share", "Spearman rho (p)"], stim_rows)}</div>
</body></html>
"""
