"""attneave.stimuli: shapes, curvature and the information they carry."""

__version__ = "0.1.0"
