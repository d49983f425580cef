"""The statistics of point selection.

``design`` (the used clicks as indices), ``choice`` (the conditional-logit
model), ``blurred`` (the same observed through localisation error),
``mixed`` (crossed random slopes for participants and stimuli), ``group``
(Monte Carlo group and items tests), ``circular`` (circular statistics),
``effect`` (a portable effect size) and ``predictors`` (rival predictions).
"""
