"""Stimulus shapes: generators (Attneave polygons, radial-frequency and
Fourier shapes, superformula, blobs), deformations matched in size, and
information-guided stimuli (fragments, Attneave's cat, dots)."""
