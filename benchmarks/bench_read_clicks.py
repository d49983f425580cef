"""Reading a large click file: the tolerant reader against pandas' C parser.

Anchor: ``pandas.read_csv(path, dtype=str, keep_default_na=False)``, the
strict reader the project used before (it refuses a file with one bad row
and does not sniff separators or decimal commas). Project:
``attneave.analysis.clicks.read.read_clicks`` on the same file (separator and decimal
sniffing, line numbers, per-row field-count check), once on a clean
comma file and once on the same rows as a ';'-separated file with decimal
commas and one malformed row.

Prints medians of repeated runs and the ratio to the anchor.
Usage: python benchmarks/bench_read_clicks.py [--rows 1000000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from _machine import header, median_time  # noqa: E402


def write_files(d, rows, seed=0):
    import pandas as pd

    rng = np.random.default_rng(seed)
    df = pd.DataFrame(dict(
        participant=np.char.add("P", (rng.integers(0, 40, rows)).astype(str)),
        stimulus_id=np.char.add("rf_", (rng.integers(0, 100, rows)).astype(str)),
        x=rng.uniform(0, 512, rows).round(3), y=rng.uniform(0, 512, rows).round(3),
        click=rng.integers(1, 10, rows), trial=rng.integers(0, 100, rows), rt_ms=rng.integers(200, 5000, rows),
    ))
    comma = os.path.join(d, "clicks.csv")
    df.to_csv(comma, index=False)
    euro = os.path.join(d, "clicks_eu.csv")
    text = df.to_csv(index=False, sep=";", decimal=",")
    lines = text.split("\n")
    lines[len(lines) // 2] += ";extra"  # one malformed row
    with open(euro, "w") as fh:
        fh.write("\n".join(lines))
    return comma, euro


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()

    import pandas as pd

    from attneave.analysis.clicks.read import read_clicks

    header(f"read_clicks, {a.rows:,} rows, median of {a.repeats}")
    with tempfile.TemporaryDirectory() as d:
        comma, euro = write_files(d, a.rows)
        print(f"file: {os.path.getsize(comma) / 1e6:.1f} MB")
        t_anchor = median_time(lambda: pd.read_csv(comma, dtype=str, keep_default_na=False), a.repeats)
        t_comma = median_time(lambda: read_clicks(comma), a.repeats)
        t_euro = median_time(lambda: read_clicks(euro), a.repeats)
        df = read_clicks(euro)
        assert len(df) == a.rows and (df["row_error"] != "").sum() == 1
    print(f"anchor pandas.read_csv (C, strict): {t_anchor:.2f} s")
    print(f"read_clicks, comma file:           {t_comma:.2f} s  ratio {t_comma / t_anchor:.2f}")
    print(f"read_clicks, ';' + decimal commas:  {t_euro:.2f} s  ratio {t_euro / t_anchor:.2f}")


if __name__ == "__main__":
    main()
