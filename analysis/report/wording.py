"""Words for report.html: parameters with their units, predictors by name, and the references.

The summary keeps identifiers and Python values (``click_sd: null``,
``length_unit: "sample"``) for programs; a reader of the report gets them in
words: :func:`parameter_rows` turns ``summary["params"]`` into rows of
(parameter, value with unit, meaning), and :data:`PREDICTOR_NAMES` names the
predictors. :data:`REFERENCES` holds the works the method text cites, in
APA style.

Examples
--------
>>> parameter_rows({"click_sd": None, "level": 0.95})[1][:2]
('Confidence level', '95%')
>>> parameter_rows({"click_sd": None})[0][1]
'not modelled'
>>> parameter_rows({"click_sd": 2.5})[0][1]
'2.5 px (SD along the contour)'
"""

from __future__ import annotations

import html

__all__ = ["PREDICTOR_NAMES", "REFERENCES", "predictor_name", "parameter_rows", "references_html"]

#: Predictors in words (identifiers in summary.json, models.csv).
PREDICTOR_NAMES = {
    "surprisal": "surprisal (eq. 5; tested)",
    "abs_curvature": "|curvature|",
    "concavity": "concavity (minima rule)",
    "convexity": "convexity",
    "extremum_proximity": "nearness to a curvature extremum",
    "medial_axis": "medial-axis (skeleton) salience",
    "uniform": "uniform clicking (no predictor)",
}

#: The works cited, by key, in APA style (HTML).
REFERENCES = {
    "akaike": "Akaike, H. (1974). A new look at the statistical model identification. <i>IEEE Transactions on "
              "Automatic Control, 19</i>(6), 716&ndash;723.",
    "attneave": "Attneave, F. (1954). Some informational aspects of visual perception. <i>Psychological Review, "
                "61</i>(3), 183&ndash;193.",
    "baayen": "Baayen, R. H., Davidson, D. J., &amp; Bates, D. M. (2008). Mixed-effects modeling with crossed random "
              "effects for subjects and items. <i>Journal of Memory and Language, 59</i>(4), 390&ndash;412.",
    "breslow": "Breslow, N. E., &amp; Clayton, D. G. (1993). Approximate inference in generalized linear mixed "
               "models. <i>Journal of the American Statistical Association, 88</i>(421), 9&ndash;25.",
    "clark": "Clark, H. H. (1973). The language-as-fixed-effect fallacy: A critique of language statistics in "
             "psychological research. <i>Journal of Verbal Learning and Verbal Behavior, 12</i>(4), 335&ndash;359.",
    "feldman": "Feldman, J., &amp; Singh, M. (2005). Information along contours and object boundaries. "
               "<i>Psychological Review, 112</i>(1), 243&ndash;252.",
    "hoffman": "Hoffman, D. D., &amp; Richards, W. A. (1984). Parts of recognition. <i>Cognition, 18</i>, "
               "65&ndash;96.",
    "holmes": "Holmes, A. P., &amp; Friston, K. J. (1998). Generalisability, random effects and population "
              "inference. <i>NeuroImage, 7</i>, S754.",
    "mcfadden": "McFadden, D. (1974). Conditional logit analysis of qualitative choice behavior. In P. Zarembka "
                "(Ed.), <i>Frontiers in econometrics</i> (pp. 105&ndash;142). Academic Press.",
    "ziatdinov": "Ziatdinov, R. (2016). Visual perception, quantity of information function and the concept of the "
                 "quantity of information continuous splines. <i>Scientific Visualization, 8</i>(1).",
}


def predictor_name(key):
    """A predictor's name in words ('|curvature|'); unknown keys with their underscores as spaces."""
    return PREDICTOR_NAMES.get(key, str(key).replace("_", " "))


def references_html():
    """The reference list, sorted by first author (APA: unnumbered, cited by author and year), as HTML."""
    items = "".join(f"<li>{REFERENCES[k]}</li>" for k in sorted(REFERENCES))
    return f'<ul class="refs">{items}</ul>'


_UNITS = {
    "sample": "the sample spacing (&Delta;s = 1)",
    "perimeter": "perimeters (&Delta;s = 1/n on a closed contour)",
    "radius": "radii of the circle of equal area",
    "px": "image pixels (&Delta;s = L/n px)",
}
_COORDS = {
    "image": "image pixels, origin at the top-left pixel, y down",
    "centered": "pixels from the image centre",
    "pix": "window pixels from the window centre",
    "height": "window height units from the window centre",
    "norm": "normalised window units (-1 to 1) from the window centre",
}


def _rule(v):
    """A '0.05 x image diagonal' rule in words."""
    if isinstance(v, dict):
        v = v.get("rule", v.get("px"))
    return html.escape(str(v)).replace(" x ", " &times; ")


def _num(v):
    return f"{v:g}" if isinstance(v, (int, float)) and not isinstance(v, bool) else html.escape(str(v))


def parameter_rows(p):
    """Rows ``(parameter, value, meaning)`` of ``summary["params"]`` in words and units (HTML-safe).

    Known keys come first, in the order a method section gives them; any
    other key follows with its name's underscores as spaces.
    """
    rows = []

    def add(key, label, value, meaning=""):
        if key in p:
            rows.append((label, value, meaning))

    g = p.get
    add("n", "Points per contour (n)", f"{_num(g('n'))} equally spaced points",
        "the choice set of every click; surprisal is computed at these points")
    add("model", "Form of surprisal", "eq. 5 of Ziatdinov (2016)" if g("model") == "paper"
        else "von Mises form (Feldman &amp; Singh, 2005)", "the two give the same standardised z")
    add("A", "A&prime; (eq. 5)", _num(g("A")), "constant of eq. 5 (dimensionless); shifts surprisal, not z")
    add("b", "b (eq. 5)", _num(g("b")), "concentration of turning angles (per unit length squared)")
    add("length_unit", "Unit of arc length in eq. 5", _UNITS.get(g("length_unit"), _num(g("length_unit"))), "")
    add("units", "Unit of surprisal", _num(g("units")), "")
    add("coords", "Click coordinates", _COORDS.get(g("coords"), _num(g("coords"))), "")
    if "window_size" in p:
        w = g("window_size")
        add("window_size", "Window size", "not used" if not w else f"{_num(w[0])} &times; {_num(w[1])} px",
            "" if w else "clicks were not given in window units")
    add("scale", "Shown size / image size", _num(g("scale")), "1: images were shown at their own size")
    add("tolerance", "Largest click&ndash;contour distance", _rule(g("tolerance")),
        "farther clicks are excluded (also from what was drawn, on fragments and dots)")
    add("bandwidth", "Kernel SD of the click density", _rule(g("bandwidth")), "along the contour")
    add("peak_tolerance", "Peak hit window", _rule(g("peak_tolerance")), "a click this close to a peak is a hit")
    if "click_sd" in p:
        sd = g("click_sd")
        add("click_sd", "Click localisation error", "not modelled" if sd is None
            else f"{_num(sd)} px (SD along the contour)",
            "each click taken as a choice of its nearest point" if sd is None
            else "the pooled fits are observed through this error")
    add("level", "Confidence level", f"{100 * g('level'):g}%" if isinstance(g("level"), float) else _num(g("level")))
    add("group_simulations", "Monte Carlo replicates R", _num(g("group_simulations")),
        "null of the group and items tests; smallest possible p = 1/(R + 1)")
    add("permutations", "Circular shifts per stimulus", _num(g("permutations")), "null of Spearman's rho")
    add("grid", "Positions along each contour", _num(g("grid")), "where click density and surprisal are correlated")
    add("seed", "Random seed", _num(g("seed")), "of every Monte Carlo step")
    add("choice_model", "Choice model", "p(j) = exp(&beta; z<sub>j</sub>) / &Sigma;<sub>i</sub> exp(&beta; "
        "z<sub>i</sub>) over the n points", "conditional logit (McFadden, 1974); z: surprisal standardised per "
        "stimulus" + ("" if g("click_sd") is None else ", observed through the click error"))
    known = {"n", "model", "A", "b", "length_unit", "units", "coords", "window_size", "scale", "tolerance",
             "bandwidth", "peak_tolerance", "click_sd", "level", "group_simulations", "permutations", "grid",
             "seed", "choice_model"}
    for k in sorted(set(p) - known):
        rows.append((html.escape(str(k).replace("_", " ").capitalize()), "not given" if p[k] is None else _rule(p[k]),
                     ""))
    return rows
