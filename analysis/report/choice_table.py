"""The choice data in long format, and an R script that fits the same models.

``points.csv``
    One row per stimulus and contour point: ``stimulus_id, point`` and the
    standardised value ``z_<name>`` of every predictor.
``choices.csv``
    The long format of a conditional logit: one row per used click and
    contour point, ``choice_set`` (the click), ``participant``,
    ``stimulus_id``, ``point``, ``chosen`` (1 at the clicked point) and the
    predictors. It has (used clicks x n) rows, so it is written only up to
    :data:`MAX_CHOICE_ROWS`; beyond, the R script builds it from
    ``clicks.csv`` and ``points.csv``.
``analysis.R``
    ``survival::clogit`` for the pooled model and ``mclogit::mclogit`` with
    crossed random slopes for participants and stimuli.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAX_CHOICE_ROWS", "points_table", "choices_table", "r_script"]

#: Largest choices.csv written (rows); 2,000,000 rows are about 100 MB.
MAX_CHOICE_ROWS = 2_000_000


def points_table(analysis, names):
    """``stimulus_id, point, z_<name>...`` for every stimulus and point."""
    import pandas as pd

    ids = list(analysis.profiles["ids"])
    n = analysis.predictions[ids[0]].n
    cols = dict(stimulus_id=np.repeat(ids, n), point=np.tile(np.arange(n), len(ids)))
    for k in names:
        cols[f"z_{k}"] = np.concatenate([analysis.predictions[s].z[k] for s in ids])
    return pd.DataFrame(cols)


def choices_table(analysis, names):
    """The long-format choice table, or None when it would exceed :data:`MAX_CHOICE_ROWS` rows."""
    import pandas as pd

    c = analysis.clicks
    used = c.loc[~c["excluded"].to_numpy(dtype=bool), ["participant", "stimulus_id", "point"]]
    ids = list(analysis.profiles["ids"])
    n = analysis.predictions[ids[0]].n
    U = len(used)
    if U * n > MAX_CHOICE_ROWS:
        return None
    sid = used["stimulus_id"].to_numpy(dtype=object)
    clicked = used["point"].to_numpy(dtype=np.int64)
    point = np.tile(np.arange(n), U)
    cols = dict(choice_set=np.repeat(np.arange(1, U + 1), n),
                participant=np.repeat(used["participant"].to_numpy(dtype=object), n),
                stimulus_id=np.repeat(sid, n), point=point,
                chosen=(point == np.repeat(clicked, n)).astype(np.int8))
    index = {s: i for i, s in enumerate(ids)}
    srow = np.repeat(np.array([index[s] for s in sid], dtype=np.int64), n)
    for k in names:
        Z = np.stack([analysis.predictions[s].z[k] for s in ids])
        cols[f"z_{k}"] = Z[srow, point]
    return pd.DataFrame(cols)


def r_script(names, version, choices_written):
    """An R script fitting the pooled and the mixed conditional logit to the written tables."""
    rhs = " + ".join(f"z_{k}" for k in names)
    first = f"z_{names[0]}"
    build = ('d <- read.csv("choices.csv")' if choices_written else
             '''# choices.csv was too large to write: build it from the used clicks and the points
cl <- read.csv("clicks.csv")
cl <- cl[!as.logical(cl$excluded), c("participant", "stimulus_id", "point")]
cl$choice_set <- seq_len(nrow(cl))
names(cl)[names(cl) == "point"] <- "clicked"
d <- merge(cl, pts, by = "stimulus_id")
d$chosen <- as.integer(d$point == d$clicked)
d <- d[order(d$choice_set, d$point), ]''')
    return f'''# Written by attneave {version} (attneave analyze): the choice models of summary.json in R.
# p(point j of a stimulus) ~ exp(sum_k coef_k * z_kj); one choice set per used click.
# Needs: install.packages(c("survival", "mclogit"))   (random slopes need mclogit >= 0.9)
pts <- read.csv("points.csv")
{build}

# the pooled model (summary.json: beta_hat for surprisal alone, "predictors" when fitted jointly)
library(survival)
pooled <- clogit(chosen ~ {rhs} + strata(choice_set), data = d)
print(summary(pooled))

# crossed random slopes for participants and stimuli (summary.json: "mixed", fitted there by a
# Laplace approximation; mclogit uses penalised quasi-likelihood, so the figures differ slightly)
library(mclogit)
mixed <- mclogit(cbind(chosen, choice_set) ~ {first},
                 random = list(~ 0 + {first} | participant, ~ 0 + {first} | stimulus_id), data = d)
print(summary(mixed))
'''
