"""The used clicks of an analysis as indices into stimuli, participants and points."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from attneave.analysis.clicks.mapping import PREDICTORS

__all__ = ["Design", "design", "mean_by"]


@dataclass
class Design:
    """The used clicks as indices into stimuli, participants and points.

    ``sidx, pidx, j`` (U,) stimulus, participant and point of each used click,
    ``t`` its arc position, ``zc`` the z of the tested prediction there;
    ``Z`` (S, n) that prediction standardised, ``Zs`` every predictor's z;
    ``Ms`` (S,) clicks per stimulus, ``Mgs`` (G, S) per participant and
    stimulus (a scipy.sparse CSR matrix: a participant sees few of many
    stimuli, and G x S dense would not fit for large designs), ``Cs`` (S, n)
    per stimulus and point.
    """

    ids: list
    participants: list
    sidx: np.ndarray
    pidx: np.ndarray
    t: np.ndarray
    j: np.ndarray
    zc: np.ndarray
    perim: np.ndarray
    npts: int
    Z: np.ndarray
    Zs: dict
    sign: np.ndarray
    Ms: np.ndarray
    Mgs: np.ndarray
    Cs: np.ndarray

    @property
    def S(self):
        return len(self.ids)

    @property
    def G(self):
        return len(self.participants)

    @property
    def U(self):
        return len(self.t)

    @property
    def constant(self):
        return np.all(self.Z == 0, axis=1)


def mean_by(index, size, values, mask=None):
    """Mean of `values` per group `index` (NaN for a group without values)."""
    w = np.ones(len(index)) if mask is None else mask.astype(float)
    num = np.bincount(index, weights=values * w, minlength=size)
    den = np.bincount(index, weights=w, minlength=size)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, num / den, np.nan)


def design(mapped, predictions, ids):
    """Index the used clicks of `mapped` (from :func:`map_clicks`)."""
    import pandas as pd
    import scipy.sparse

    used = ~mapped["excluded"].to_numpy()
    sindex = {s: i for i, s in enumerate(ids)}
    part_all = mapped["participant"].to_numpy(dtype=object)
    # a header line repeated inside the file holds the column's name, not a participant
    header = (mapped["reason"] == "repeated_header").to_numpy() if "reason" in mapped.columns else False
    participants = sorted(set(pd.unique(part_all[~header])) - {""})
    S, G = len(ids), len(participants)
    sidx = mapped["stimulus_id"].map(sindex).to_numpy()[used].astype(np.int64)
    pidx = pd.Categorical(part_all[used], categories=participants).codes.astype(np.int64)
    j = mapped["point"].to_numpy()[used].astype(np.int64)
    npts = predictions[ids[0]].n
    return Design(
        ids=ids, participants=participants, sidx=sidx, pidx=pidx, t=mapped["t"].to_numpy()[used], j=j,
        zc=mapped["z"].to_numpy()[used], perim=np.array([predictions[s].perimeter for s in ids]), npts=npts,
        Z=np.stack([predictions[s].z["surprisal"] for s in ids]),
        Zs={k: np.stack([predictions[s].z[k] for s in ids]) for k in PREDICTORS},
        sign=np.stack([predictions[s].sign for s in ids]),
        Ms=np.bincount(sidx, minlength=S).astype(float),
        # duplicates (several clicks of a participant on a stimulus) are summed by the conversion
        Mgs=scipy.sparse.csr_matrix((np.ones(len(sidx)), (pidx, sidx)), shape=(G, S)),
        Cs=np.bincount(sidx * npts + j, minlength=S * npts).reshape(S, npts).astype(float),
    )
