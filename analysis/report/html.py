"""report.html: the analysis written as a methods-and-results section.

One self-contained page: the software and date, the design and exclusions,
the prediction and every parameter, the models, and the results in APA style
(numbers to sensible precision, p as ``p = .023`` or ``p < .001``), the
figures with captions that say what they show (each also as SVG beside the
PNG), compact numbered tables placed after the text that cites them, and a
reference list (:mod:`attneave.analysis.report.wording` holds the words for
parameters and predictors and the references). Estimates that cannot be
trusted are flagged rather than printed as numbers: a per-stimulus or
per-participant beta at the search bound or with an infinite standard error,
Spearman's rho on a stimulus whose clicks all fall on one point, and a
random-effect SD estimated at zero (the boundary of its range) is said in
words. When a rival predictor fits better than surprisal, the text says so.

The page is one column with no scroll boxes, so that printing it (or a
full-page capture) keeps every row of every table; at narrow widths long
identifiers wrap rather than widen the page.
"""

from __future__ import annotations

import base64
import html
import math

from attneave.analysis.report.wording import parameter_rows, predictor_name, references_html

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


def _raw_table(header, rows, cls=""):
    """:func:`_table` for cells that are HTML already (escaped where they hold data)."""
    head = "".join(f"<th>{h}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>" for r in rows)
    return f'<table class="{cls}"><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>'


#: Exclusion reasons in words (clicks.csv has the identifiers).
REASON_WORDS = {
    "repeated_header": "repeated header lines (no clicks)",
    "empty_row": "rows of separators only (no clicks)",
    "malformed_row": "rows with a wrong number of fields",
    "missing_coordinate": "missing x or y",
    "non_numeric_coordinate": "x or y not a number",
    "coordinate_list": "x and y lists of different lengths",
    "coordinate_out_of_range": "coordinates beyond 10^12",
    "unknown_stimulus": "unknown stimulus",
    "missing_participant": "no participant id",
    "outside_image": "outside the image",
    "far_from_contour": "farther from the contour than the tolerance",
    "off_drawn_part": "far from every drawn part (gaps of fragment, dot and polygon stimuli)",
}


def _drawn(analysis):
    """Stimulus id -> DrawnParts for the stimuli that showed only part of their contour."""
    return {k: pr.drawn for k, pr in analysis.predictions.items() if getattr(pr, "drawn", None) is not None}


def _stimulus_rows(a, drawn):
    from attneave.analysis.clicks.drawn import describe

    ps = a.per_stimulus
    c = a.clicks
    off = c.loc[c["reason"] == "off_drawn_part", "stimulus_id"].value_counts()
    # distinct points chosen per stimulus, in one pass (a filter per stimulus is quadratic in the set)
    distinct = c.loc[~c["excluded"]].groupby("stimulus_id", sort=False)["point"].nunique()
    rows, notes = [], []
    for r in ps.itertuples():
        rho = "n/a" if not math.isfinite(r.spearman_rho) else f"{num(r.spearman_rho)} ({pval(r.spearman_p, False)})"
        if r.n_used > 0 and not r.constant_prediction:
            if distinct.get(r.stimulus_id, 0) == 1:
                rho += " *"
                notes.append(r.stimulus_id)
        # a stimulus nobody clicked has no estimate at all, not one with an infinite SE
        beta = "n/a (no used clicks)" if r.n_used == 0 else _flagged_beta(r.beta_hat, r.beta_se, r.beta_at_bound)
        row = [r.stimulus_id]
        if drawn:
            d = drawn.get(r.stimulus_id)
            row += ["whole contour" if d is None else describe(d), int(off.get(r.stimulus_id, 0))]
        rows.append(row + [r.n_used, beta, num(r.mean_z), _pct(r.top_share) if math.isfinite(r.top_share) else "n/a",
                           rho])
    return rows, notes


def _ci(s):
    """'95% CI', at the confidence level the analysis used (``params.level``)."""
    return f"{100 * s['params'].get('level', 0.95):g}% CI"


def _p(v):
    """:func:`pval` for HTML text: its '<' escaped."""
    return html.escape(pval(v))


def _exclusions_text(s):
    """'3 were excluded (Table 2): 2 farther from the contour than the tolerance, 1 outside the image'."""
    parts = [f"{v} {REASON_WORDS.get(k, k.replace('_', ' '))}" for k, v in s["exclusions"].items() if v]
    if not parts:
        return "none was excluded (Table 2)"
    return f"{s['n_excluded']} {'was' if s['n_excluded'] == 1 else 'were'} excluded (Table 2): " + "; ".join(parts)


def _zero_sd(m):
    """A sentence for random-effect SDs estimated at zero, or ''."""
    zero = [who for key, who in (("sd_participant", "participants"), ("sd_stimulus", "stimuli"))
            if m.get(key) is not None and m[key] < 0.005]
    if not zero:
        return ""
    who = " and across ".join(zero)
    return (f" The SD of the slope across {who} was estimated at zero, the boundary of its range: these data show "
            f"no variation of the weight of surprisal across {who} beyond what the randomness of the clicks "
            f"explains, so the model treats them as alike (as the pooled fit does), and its interval does not "
            f"allow for such variation.")


def _rivals(s):
    """Sentences naming the predictors that fit better than surprisal, alone or added to it."""
    models = s.get("models") or {}
    sur = models.get("surprisal")
    out = []
    if sur and sur.get("aic") is not None:
        better = sorted(((k, v) for k, v in models.items() if k != "surprisal" and v.get("aic") is not None
                         and v["aic"] < sur["aic"]), key=lambda kv: kv[1]["aic"])
        if better:
            names = ", ".join(f"{predictor_name(k)} (AIC lower by {sur['aic'] - v['aic']:.1f})" for k, v in better)
            out.append(f"Surprisal was not the best predictor of where people clicked: {esc_(names)} fitted the "
                       f"clicks better on its own (Table 4; Akaike, 1974).")
        else:
            out.append("Of the predictors fitted one at a time, surprisal fitted the clicks best (Table 4; Akaike, "
                       "1974).")
    joint = {k: v for k, v in (s.get("predictors") or {}).items() if k != "surprisal"}
    adds = [k for k, v in joint.items() if not v.get("at_bound") and v.get("lr_p") is not None and v["lr_p"] < 0.05]
    if adds:
        out.append(f"Fitted jointly with surprisal, {esc_(', '.join(predictor_name(k) for k in adds))} still "
                   f"improved the fit (likelihood-ratio test, Table 3).")
    return " ".join(out)


def esc_(v):
    return html.escape(str(v))


def _results(s, n_figures):
    g, it, m, e = s["group"], s["by_stimulus"], s.get("mixed") or {}, s["effect"]
    out = [
        f"{_pct(e['top_share'])} of the used clicks fell on the top {100 * e['fraction']:.0f}% of their contour's "
        f"points by surprisal, against {_pct(e['chance_share'])} expected by chance (lift = {num(e['lift'])})."]
    if m.get("beta") is not None:
        out.append(
            f"In the mixed conditional logit with crossed random slopes, the mean weight of standardised surprisal "
            f"was &beta; = {num(m['beta'])}, {_ci(s)} [{num(m['ci_low'])}, {num(m['ci_high'])}] (t quantiles, df = "
            f"{m['df']}), with SD = {num(m['sd_participant'])} across participants and SD = {num(m['sd_stimulus'])} "
            f"across stimuli." + _zero_sd(m))
    out.append(
        f"The group test across participants gave {_t_df(g)} = {t_text(g)}, {_p(g['p_value'])} "
        f"(one-sided, Monte Carlo null of uniform clicking, R = {g['simulations']}), d<sub>z</sub> = "
        f"{num(g['effect_size'])}; the items test across stimuli {_t_df(it)} = {t_text(it)}, "
        f"{_p(it['p_value'])}" + (" (Figure 1, left)." if n_figures else "."))
    if s["beta_at_bound"]:  # the bound and an interval around it are no estimate: flagged, not printed
        out.append(f"The pooled fit (clicks treated as independent) reached the "
                   f"{'upper' if s['beta_hat'] > 0 else 'lower'} bound of its search: &beta; is not estimable "
                   f"(near-separation).")
    else:
        out.append(
            f"The pooled fit (clicks treated as independent) gave &beta; = {num(s['beta_hat'])}, {_ci(s)} "
            f"[{num(s['beta_ci'][0])}, {num(s['beta_ci'][1])}].")
    out.append(_rivals(s))
    sp = s["spearman"]
    out.append(f"Click density correlated with surprisal along the contours with mean Spearman rho = "
               f"{num(sp['mean_rho'])}, {_p(sp['p_value'])} (circular shifts), over {sp['n_stimuli']} stimuli.")
    return " ".join(x for x in out if x)


def _method(s, p, drawn):
    left_out = "; ".join(f"{predictor_name(k)}: {v}" for k, v in s.get("models_left_out", {}).items())
    rivals = [predictor_name(k) for k in s.get("models", {}) if k not in ("surprisal", "uniform")]
    text = [
        f"Each click was mapped to the nearest point of its stimulus's contour and excluded beyond "
        f"{esc_(p['tolerance']['rule']).replace(' x ', ' &times; ')} from it. The prediction is the surprisal "
        f"(quantity of information) of eq. 5 of Ziatdinov (2016), the curvature form of Feldman and Singh's (2005) "
        f"model of information along contours, after Attneave (1954), computed at n = {p['n']} equally spaced "
        f"points per contour and standardised per stimulus (z: mean 0, SD 1); Table 1 gives every parameter with "
        f"its unit. Clicks were modelled as a discrete choice among the n points, p(j) &prop; exp(&beta; "
        f"z<sub>j</sub>), a conditional logit (McFadden, 1974), fitted pooled, jointly with the predictors "
        f"{esc_(', '.join(predictor_name(k) for k in s['predictors']))}, and as a mixed model with crossed random "
        f"slopes for participants and stimuli (Baayen et al., 2008), by the Laplace approximation (Breslow &amp; "
        f"Clayton, 1993). The group test compares per-participant mean z with its Monte Carlo null under uniform "
        f"clicking (R = {p['group_simulations']}; Holmes &amp; Friston, 1998); the items test does the same across "
        f"stimuli (Clark, 1973). The portable effect size is the share of clicks on the top "
        f"{100 * s['effect']['fraction']:.0f}% of points.",
        (f"Rival predictors, each fitted alone and compared by AIC (Akaike, 1974): {esc_(', '.join(rivals))}"
         + ("; the minima rule is that of Hoffman and Richards (1984). " if "concavity" in s.get("models", {})
            else ". ") if rivals else "")
        + "The von Mises form of surprisal is not a rival: standardised, it equals the paper's form."
        + (f" Left out as identical to another predictor: {esc_(left_out)}." if left_out else ""),
        # the models of --models that did not run, and why (summary.json: models_skipped)
        *(["Models not run: " + "; ".join(f"{esc_(k)} ({esc_(v)})" for k, v in s["models_skipped"].items()) + "."]
          if s.get("models_skipped") else [])]
    if drawn:
        kinds = {}
        for d in drawn.values():
            kinds[d.mode] = kinds.get(d.mode, 0) + 1
        what = ", ".join(f"{v} as {'a polygon (Attneave&rsquo;s cat)' if k == 'polygon' else k}"
                         for k, v in sorted(kinds.items()))
        text.append(
            f"{len(drawn)} stimuli showed only part of their contour ({what}; the stimulus set's manifest says "
            f"what was drawn). A click farther than the same tolerance from everything drawn on its stimulus (in a "
            f"gap between fragments, between dots, or off the polygon) was excluded as <i>off drawn part</i> and is "
            f"counted separately (Table 2; <code>exclusions.off_drawn_part</code> in summary.json). The choice set "
            f"stays the n points of the whole contour, undrawn ones included: on a stimulus that shows only its "
            f"surprisal peaks, clicks on what was drawn fall on high-surprisal points by construction, so for such "
            f"stimuli the comparison of interest is between conditions (peaks against troughs of one shape, same "
            f"visible length), not each against uniform clicking.")
    return "".join(f"<p>{t}</p>" for t in text)


CSS = """
body { font-family: Georgia, serif; margin: 2em auto; max-width: 1100px; padding: 0 1em; line-height: 1.45; }
h1, h2, h3 { font-family: sans-serif; } h3 { font-size: 105%; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 90%; max-width: 100%; }
th, td { border-bottom: 1px solid #ccc; padding: 3px 10px; text-align: left; overflow-wrap: anywhere;
         vertical-align: top; }
thead th { border-bottom: 2px solid #333; overflow-wrap: normal; }
img { max-width: 100%; height: auto; } figure { margin: 1em 0 2em; }
figcaption { font-size: 90%; } .warn { color: #a00; } code { font-size: 90%; overflow-wrap: anywhere; }
.refs { list-style: none; padding-left: 0; } .refs li { margin-bottom: 0.3em; padding-left: 2em; text-indent: -2em; }
@media print {
  body { max-width: none; margin: 0; font-size: 10pt; }
  thead { display: table-header-group; }
  tr, figure { break-inside: avoid; }
  h2, h3 { break-after: avoid; }
}
"""


def render(analysis, summary, figures):
    """The page. `figures`: list of (stem, caption, png bytes, svg file name)."""
    esc = html.escape
    s, p = summary, summary["params"]
    drawn = _drawn(analysis)
    excl = [[esc(REASON_WORDS.get(k, k.replace("_", " "))), f"<code>{esc(k)}</code>", v]
            for k, v in s["exclusions"].items() if v] or [["none", "", 0]]
    excl.append(["<b>total excluded</b>", "", f"<b>{s['n_excluded']}</b> of {s['n_clicks']}"])
    pred_rows = [[predictor_name(k), "at bound" if v.get("at_bound") else num(v["coef"]),
                  "n/a" if v.get("at_bound") else f"[{num(v['ci_low'])}, {num(v['ci_high'])}]",
                  "at bound" if v.get("at_bound") else pval(v["lr_p"], False)] for k, v in s["predictors"].items()]
    models = [[predictor_name(r.model), "at bound" if r.at_bound else num(r.beta_hat), num(r.loglik, 1),
               num(r.delta_aic, 1)] for r in analysis.models.itertuples()]
    stim_rows, single = _stimulus_rows(analysis, drawn)
    flagged = int(analysis.per_stimulus["beta_at_bound"].sum())
    params = [[a, b, c] for a, b, c in parameter_rows(p)]
    figs = "\n".join(
        f'<figure><img alt="{esc(stem)}" src="data:image/png;base64,{base64.b64encode(png).decode("ascii")}">'
        f'<figcaption><b>Figure {i + 1}.</b> {esc(cap)} (<a href="figures/{esc(svg)}">SVG</a>)</figcaption></figure>'
        for i, (stem, cap, png, svg) in enumerate(figures))
    warn = "".join(f"<p class=warn>{esc(w)}</p>" for w in s.get("warnings", []))
    counts = (f"Of {s['n_clicks']} clicks, {s['n_used']} were used from "
              f"{_count(s['n_participants_used'], 'participant')} on {s['n_stimuli_clicked']} of "
              f"{_count(s['n_stimuli'], 'stimulus', 'stimuli')}; {_exclusions_text(s)}.")
    stim_head = ["stimulus"] + (["shown", "clicks off drawn part"] if drawn else []) + [
        "used clicks", "beta (SE)", "mean z", "top share", "Spearman rho (p)"]
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width">
<title>attneave analysis</title>
<style>{CSS}</style></head><body>
<h1>Clicks against predicted information along contours</h1>
<p>attneave {esc(str(s.get('version')))}, run {esc(str(s.get('date')))}; clicks: <code>{esc(_files((s.get('inputs') or {}).get('clicks', 'n/a')))}</code>,
stimuli: <code>{esc(str((s.get('inputs') or {}).get('stimuli', 'n/a')))}</code>.</p>
{warn}
<h2>Method</h2>
{_method(s, p, drawn)}
<h3>Table 1. Parameters</h3>
{_raw_table(["parameter", "value", "meaning"], params, "params")}
<h2>Results</h2>
<p>{counts}</p>
<h3>Table 2. Exclusions</h3>
{_raw_table(["reason", "in clicks.csv", "clicks"], excl)}
<p>{_results(s, len(figures))}</p>
<h3>Table 3. Predictors fitted jointly</h3>
{_table(["predictor", "coefficient", _ci(s), "LR test p (without it)"], pred_rows)}
<h3>Table 4. Each predictor alone (models.csv)</h3>
{_table(["model", "beta", "log-likelihood", "delta AIC"], models)}
<h2>Figures</h2>
{figs or '<p>(figures not drawn)</p>'}
<h3>Table 5. Per stimulus</h3>
<p>beta (SE) from the stimulus's clicks alone; {flagged} fit(s) at the search bound are flagged, not estimated.
{'* every used click on this stimulus fell on one point: its Spearman correlation ranks a single spike and is not interpretable (' + esc(', '.join(single)) + ').' if single else ''}</p>
{_table(stim_head, stim_rows, "per-stimulus")}
<h2>References</h2>
{references_html()}
</body></html>
"""
