"""Click files in, clicks on contours out.

``read``
    Reading one click file and converting its coordinates to image pixels.
``dialects``
    The CSV dialects labs' tools write: separators, decimal commas, bad rows.
``layouts``
    jsPsych's data and the PsychoPy Builder data file: one row per click.
``files``
    Several click files (one per participant) read as one table.
``exclusions``
    Which stimulus a click belongs to, and which clicks were left out, why.
``mapping``
    Predictions per stimulus and the nearest contour point of every click.
"""
