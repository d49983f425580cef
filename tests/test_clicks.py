"""Click files, coordinate systems, stimulus sets and the mapping of clicks to contours."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from attneave.analysis.clicks.mapping import map_clicks, predict
from attneave.analysis.clicks.read import (
    from_image_coords,
    parse_columns,
    parse_coordinates,
    read_clicks,
    to_image_coords,
)
from attneave.stimuli import InputError
from attneave.stimuli.stimulus_set import read_stimulus_set, write_stimulus_set


# ------------------------------------------------------------- coordinates
@pytest.mark.parametrize("W,H", [(512, 512), (513, 300), (1, 1)])
def test_centered_origin_is_the_image_centre_in_pixel_centre_coordinates(W, H):
    x, y = to_image_coords(0.0, 0.0, W, H, "centered")
    assert (x, y) == ((W - 1) / 2, (H - 1) / 2)
    # the top-left corner of the drawn image (PsychoPy: -W/2, +H/2) is the outer
    # corner of pixel (0, 0), which spans [-0.5, 0.5] with its centre at 0
    x, y = to_image_coords(-W / 2, H / 2, W, H, "centered")
    assert (x, y) == (-0.5, -0.5)
    # y up in PsychoPy: a click above the centre has a smaller row
    assert to_image_coords(0.0, 10.0, W, H, "centered")[1] == (H - 1) / 2 - 10


def test_centered_with_scale_divides_screen_pixels():
    # image shown twice as large: 20 screen pixels right of the centre is 10 image pixels
    x, y = to_image_coords(20.0, -20.0, 100, 100, "centered", scale=2.0)
    assert (x, y) == (49.5 + 10, 49.5 + 10)


def test_image_scale_uses_pixel_edges():
    # shown at 2x, shown pixels 0 and 1 cover image pixel 0: their shared edge
    # (x = 0.5 in shown pixel-centre coordinates) is the centre of image pixel 0
    assert to_image_coords(0.5, 0.5, 10, 10, "image", scale=2.0) == (0.0, 0.0)
    assert to_image_coords(-0.5, -0.5, 10, 10, "image", scale=2.0) == (-0.5, -0.5)


@settings(max_examples=60, deadline=None)
@given(
    x=st.floats(-1000, 1000), y=st.floats(-1000, 1000), W=st.integers(1, 4000), H=st.integers(1, 4000),
    coords=st.sampled_from(["image", "centered", "pix", "height", "norm"]), scale=st.floats(0.1, 10),
)
def test_coordinate_round_trip(x, y, W, H, coords, scale):
    a, b = from_image_coords(x, y, W, H, coords, scale, window=(1920, 1080))
    x2, y2 = to_image_coords(a, b, W, H, coords, scale, window=(1920, 1080))
    assert x2 == pytest.approx(x, abs=1e-9) and y2 == pytest.approx(y, abs=1e-9)


def test_bad_coords_and_scale_raise():
    with pytest.raises(InputError, match="--coords"):
        to_image_coords(0, 0, 1, 1, "psychopy")
    with pytest.raises(InputError, match="--scale"):
        to_image_coords(0, 0, 1, 1, "image", scale=0)


def test_parse_coordinates_tells_missing_from_text():
    v, p = parse_coordinates(["1.5", "", "NaN", "abc", "inf", "1e3", " 7 ", "NA"])
    assert p.tolist() == ["", "missing_coordinate", "missing_coordinate", "non_numeric_coordinate",
                          "non_numeric_coordinate", "", "", "missing_coordinate"]
    assert v[0] == 1.5 and v[5] == 1000 and v[6] == 7 and np.isnan(v[[1, 2, 3, 4, 7]]).all()


# ------------------------------------------------------------- click files
def test_parse_columns():
    assert parse_columns("participant=subj, x=mouse_x") == {"participant": "subj", "x": "mouse_x"}
    assert parse_columns(None) == {}
    for bad, msg in [("x", "NAME=COLUMN"), ("z=col", "unknown name 'z'"), ("x=a,x=b", "twice"), ("x=", "empty")]:
        with pytest.raises(InputError, match=msg):
            parse_columns(bad)


def test_read_clicks_maps_columns_and_passes_others_through_as_text(tmp_path):
    f = tmp_path / "c.csv"
    f.write_text("subj,stim,mouse_x,mouse_y,x,rt,code\n007,a,1.5,2,99,0.350,001\n008,b,3,4,98,1e3,\n")
    df = read_clicks(f, "participant=subj,stimulus_id=stim,x=mouse_x,y=mouse_y")
    assert list(df.columns) == ["line", "participant", "stimulus_id", "x", "y", "input_x", "rt", "code"]
    assert df["participant"].tolist() == ["007", "008"]  # not turned into numbers
    assert df["rt"].tolist() == ["0.350", "1e3"] and df["code"].tolist() == ["001", ""]
    assert df["x"].tolist() == ["1.5", "3"] and df["input_x"].tolist() == ["99", "98"]
    assert df["line"].tolist() == [2, 3]


@pytest.mark.parametrize(
    "text,msg",
    [
        ("participant,stimulus_id,x\n1,a,2\n", r"missing column\(s\) y; found 'participant', 'stimulus_id', 'x' \(3 columns\)"),
        ("", "empty file"),
        ("participant,stimulus_id,x,y\n", "no click rows"),
        ("participant,stimulus_id,x,x,y\n1,a,1,2,3\n", "appears twice"),
    ],
)
def test_read_clicks_rejects_unusable_files_in_one_line(tmp_path, text, msg):
    f = tmp_path / "c.csv"
    f.write_text(text)
    with pytest.raises(InputError, match=msg) as e:
        read_clicks(f)
    assert str(f) in str(e.value) and "\n" not in str(e.value)


def test_read_clicks_names_a_mapped_column_that_is_absent(tmp_path):
    f = tmp_path / "c.csv"
    f.write_text("participant,stimulus_id,x,y\n1,a,1,2\n")
    with pytest.raises(InputError, match=r"mouse_x \(for x\)"):
        read_clicks(f, "x=mouse_x")
    with pytest.raises(InputError, match="no such file"):
        read_clicks(tmp_path / "nope.csv")


# ----------------------------------------------------------- stimulus sets
def _square(side=100.0, x0=100.0, y0=100.0):
    # counter-clockwise on the screen (y down): top-left, bottom-left, bottom-right, top-right
    return np.array([[x0, y0], [x0, y0 + side], [x0 + side, y0 + side], [x0 + side, y0]])


def _circle(r=80.0, c=(200.0, 150.0), m=2000):
    th = np.linspace(0, 2 * np.pi, m, endpoint=False)
    return np.c_[c[0] + r * np.cos(th), c[1] + r * np.sin(th)]


@pytest.fixture()
def square_set(tmp_path):
    d = tmp_path / "set"
    write_stimulus_set(d, {"sq": _square(), "disc": _circle()}, size={"sq": (300, 300), "disc": (400, 300)})
    return d


def test_hand_built_set_without_images_is_read(square_set):
    s = read_stimulus_set(square_set)
    assert s.ids == ["sq", "disc"] and s.sizes == {"sq": (300, 300), "disc": (400, 300)}
    assert s.images == {"sq": None, "disc": None}  # image files are optional for analysis
    assert s.contours["sq"].perimeter == pytest.approx(400.0)


@pytest.mark.parametrize(
    "edit,msg",
    [
        (lambda m: m.drop(columns="width"), r"missing column\(s\) width"),
        (lambda m: m.assign(stimulus_id=["sq", "a b"]), "line 3: stimulus_id must match"),
        (lambda m: m.assign(stimulus_id=["sq", "sq"]), "line 3: stimulus_id 'sq' appears twice"),
        (lambda m: m.assign(height=["300", "-1"]), "line 3: column 'height' must be a positive"),
        (lambda m: m.assign(contour=["contours/sq.csv", "contours/none.csv"]), "line 3: contour file"),
    ],
)
def test_broken_manifest_is_named_with_its_line(square_set, edit, msg):
    m = pd.read_csv(square_set / "manifest.csv", dtype=str, keep_default_na=False)
    edit(m).to_csv(square_set / "manifest.csv", index=False)
    with pytest.raises(InputError, match=msg) as e:
        read_stimulus_set(square_set)
    assert "manifest.csv" in str(e.value)


def test_broken_contour_file_is_named(square_set):
    (square_set / "contours" / "sq.csv").write_text("x,y\n1,2\n3,4\n")
    with pytest.raises(InputError, match="sq.csv.*at least 3 distinct points"):
        read_stimulus_set(square_set)


# ------------------------------------------------------------------ mapping
def test_mapping_of_clicks_on_a_square_is_exact(square_set):
    pred = predict(read_stimulus_set(square_set), n=40)
    clicks = pd.DataFrame(
        dict(
            participant="p1",
            stimulus_id=["sq", "sq", "sq", "sq"],
            # the first point (100,100), a point 5 px outside the left edge at mid-height,
            # the bottom-right corner, and a point inside near the right edge
            x=[100.0, 95.0, 200.0, 197.0],
            y=[100.0, 150.0, 200.0, 130.0],
        )
    )
    m = map_clicks(clicks, pred)
    # the square runs (100,100) -> down the left edge -> bottom -> up the right edge
    np.testing.assert_allclose(m["t"], [0.0, 0.125, 0.5, 0.5 + 70 / 400], atol=1e-12)
    np.testing.assert_allclose(m["distance"], [0, 5, 0, 3], atol=1e-12)
    assert m["point"].tolist() == [0, 5, 20, 27]  # n = 40: point j at t = j/40
    # the corners are convex turns of pi/2 over one point: highest surprisal, percentile > 90
    assert m["surprisal_percentile"].iloc[0] > 90 and m["surprisal_percentile"].iloc[2] > 90
    assert m["surprisal_percentile"].iloc[1] < 50
    assert (m["curvature"].iloc[[0, 2]] > 0).all() and not m["excluded"].any()


def test_distance_to_a_circle_is_radius_difference(square_set):
    pred = predict(read_stimulus_set(square_set), n=64)
    ang = np.array([0.3, 2.0, 4.0])
    r = np.array([80.0, 90.0, 60.0])
    clicks = pd.DataFrame(dict(participant="p", stimulus_id="disc", x=200 + r * np.cos(ang), y=150 + r * np.sin(ang)))
    m = map_clicks(clicks, pred)
    # the polygon of 2000 points is within 80*(1-cos(pi/2000)) = 1e-4 px of the circle
    np.testing.assert_allclose(m["distance"], np.abs(r - 80), atol=2e-4)


def test_exclusion_reasons_in_order_and_nothing_dropped(square_set):
    pred = predict(read_stimulus_set(square_set), n=40)
    clicks = pd.DataFrame(
        dict(
            participant=["a", "a", "a", "a", "", "a", "a", "a", "a"],
            stimulus_id=["sq", "sq", "sq", "zz", "sq", "sq", "sq", "", "zz"],
            x=["100", "", "abc", "100", "100", "-3", "150", "100", "oops"],
            y=["150", "150", "150", "150", "150", "150", "150", "150", "1"],
            extra=list("abcdefghi"),
        )
    )
    m = map_clicks(clicks, pred, tolerance=20)
    assert m["reason"].tolist() == [
        "", "missing_coordinate", "non_numeric_coordinate", "unknown_stimulus", "missing_participant",
        "outside_image", "far_from_contour", "unknown_stimulus", "non_numeric_coordinate",
    ]
    assert m["excluded"].tolist() == [r != "" for r in m["reason"]]
    assert m["extra"].tolist() == list("abcdefghi") and m["x"].iloc[2] == "abc"
    # excluded clicks that have coordinates still get their mapping
    assert m["distance"].iloc[6] == pytest.approx(50.0)


def test_default_tolerance_is_five_percent_of_the_diagonal(square_set):
    pred = predict(read_stimulus_set(square_set), n=40)
    tol = 0.05 * np.hypot(300, 300)  # 21.2 px
    clicks = pd.DataFrame(dict(participant="a", stimulus_id="sq", x=[100 - tol + 0.1, 100 - tol - 0.1], y=150.0))
    assert map_clicks(clicks, pred)["reason"].tolist() == ["", "far_from_contour"]


# ------------------------------------------- files as PsychoPy, jsPsych and spreadsheets write them
def test_window_units_of_psychopy():
    # a 400 x 300 image drawn at the centre of a 1000 x 800 window at its own size:
    # its top-left corner (outer edge of pixel (0, 0)) is 200 px left of and 150 px above the centre
    win = (1000, 800)
    assert to_image_coords(-200 / 800, 150 / 800, 400, 300, "height", window=win) == (-0.5, -0.5)
    assert to_image_coords(-200 / 500, 150 / 400, 400, 300, "norm", window=win) == (-0.5, -0.5)
    assert to_image_coords(0.0, 0.0, 400, 300, "pix") == (199.5, 149.5)
    with pytest.raises(InputError, match="--window-size"):
        to_image_coords(0.0, 0.0, 400, 300, "height")


def test_separator_and_decimal_sniffing(tmp_path):
    from attneave.analysis.clicks.dialects import sniff_separator

    assert sniff_separator("a\tb\tc") == "\t" and sniff_separator("a|b") == "|"
    assert sniff_separator('"x;y",b') == ","  # a separator inside quotes does not count
    f = tmp_path / "c.tsv"
    f.write_text("participant\tstimulus_id\tx\ty\nP1\ta\t1,5\t-2,25\nP1\ta\t3\t4\n")
    assert read_clicks(f)[["x", "y"]].values.tolist() == [["1.5", "-2.25"], ["3", "4"]]
    # decimal commas are not guessed beside decimal points; --decimal decides
    g = tmp_path / "g.csv"
    g.write_text('participant;stimulus_id;x;y\nP1;a;1,5;2.5\n')
    assert read_clicks(g)["x"].tolist() == ["1,5"]
    assert read_clicks(g, decimal=",")["x"].tolist() == ["1.5"]
    with pytest.raises(InputError, match="seems to use ';' as separator"):
        read_clicks(g, sep=",")
    with pytest.raises(InputError, match="--sep"):
        read_clicks(g, sep="ab")


def test_malformed_rows_and_unclosed_quotes_are_flagged_not_fatal(tmp_path):
    f = tmp_path / "c.csv"
    f.write_text('participant,stimulus_id,x,y\nP1,a,1,2\nP1,a,3\nP1,a,5,6\nP1,"a,7,8\nP1,a,9,10\n')
    df = read_clicks(f)
    assert df["line"].tolist() == [2, 3, 4, 5, 6]  # the line after the open quote is a row of its own
    assert df["row_error"].tolist() == ["", "3 fields, the header has 4", "", df["row_error"].iloc[3], ""]
    assert "quote opened on line 5 is never closed" in df["row_error"].iloc[3]


def test_utf16_file_as_excel_writes_unicode_text(tmp_path):
    f = tmp_path / "c.txt"
    f.write_bytes("participant\tstimulus_id\tx\ty\r\nJosé\ta\t1\t2\r\n".encode("utf-16"))
    assert read_clicks(f)[["participant", "x"]].values.tolist() == [["José", "1"]]
    g = tmp_path / "latin1.csv"
    g.write_bytes("participant,stimulus_id,x,y\nJos\xe9,a,1,2\n".encode("latin-1"))
    with pytest.raises(InputError, match=r"line 2: not UTF-8 text"):
        read_clicks(g)


def test_coordinate_lists_are_unpacked_or_excluded(tmp_path):
    f = tmp_path / "c.csv"
    f.write_text('participant,stimulus_id,x,y,t\n'
                 'P1,a,[0.5],[1.5],[0.2]\n'
                 'P1,a,"[1, 2]","[3, 4]","[0.1, 0.2]"\n'
                 'P1,a,"[1, 2]",[3],x\n'
                 'P1,a,[],[],\n')
    df = read_clicks(f)
    assert df["line"].tolist() == [2, 3, 3, 4, 5]
    assert df["list_index"].tolist() == [-1, 0, 1, -1, -1]
    assert df["t"].tolist() == ["[0.2]", "0.1", "0.2", "x", ""]
    v, p = parse_coordinates(df["x"])
    assert v[:3].tolist() == [0.5, 1.0, 2.0]
    assert p.tolist() == ["", "", "", "coordinate_list", "missing_coordinate"]


def test_stimulus_values_match_by_id_image_path_or_file_name(tmp_path):
    from attneave.analysis.clicks.exclusions import match_stimulus_ids

    sq = np.array([[10, 10], [50, 10], [50, 50], [10, 50]], float)
    write_stimulus_set(tmp_path, {"a1": sq, "b1": sq, "c1": sq}, size=(64, 64))
    man = tmp_path / "manifest.csv"
    m = pd.read_csv(man, dtype=str, keep_default_na=False)
    m["image"] = ["set_a/shape.png", "set_b/shape.png", "images/c1.png"]
    m.to_csv(man, index=False)
    s = read_stimulus_set(tmp_path)
    ids, how = match_stimulus_ids(["a1", "x/set_b/shape.png", "D:\\exp\\set_a\\shape.png", "shape.png",
                                   "c1.jpg", " b1 ", ""], s)
    # the bare file name is shared by two images: nothing tells them apart, no guess
    assert ids.tolist() == ["a1", "b1", "a1", "shape.png", "c1", "b1", ""]
    assert how.tolist() == ["id", "image", "image", "", "file_stem", "id", ""]


def test_exclusion_report_threshold():
    from attneave.analysis.clicks.exclusions import exclusion_report

    def table(k, n):
        return pd.DataFrame(dict(reason=["far_from_contour"] * k + [""] * (n - k), excluded=[True] * k + [False] * (n - k),
                                 line=np.arange(n) + 2, stimulus_id="a"))

    assert exclusion_report(table(2, 10)) is None  # 20% is not more than 20%
    assert exclusion_report(table(3, 10)).startswith("30% of the clicks (3 of 10) were excluded: far_from_contour 3")
    assert exclusion_report(table(0, 0)) is None


@settings(max_examples=25, deadline=None)
@given(st.lists(st.sampled_from(["P1,a,1,2", "P2, b ,3.5,-4", "", "   ", "P3,c,5", "P4,d,6,7,8", "P5,e,9,10,,",
                                 ",,,", "Jos\u00e9,f,1e3,NA"]), min_size=1, max_size=30),
       st.sampled_from(["\n", "\r\n"]), st.booleans())
def test_tolerant_reader_agrees_with_the_csv_module(tmp_path_factory, body, newline, final_newline):
    # the reader's fast path (numpy field counts + pandas) against Python's csv module, line by line
    import csv

    from attneave.analysis.clicks.dialects import read_tolerant_csv

    text = newline.join(["participant,stimulus_id,x,y", *body]) + (newline if final_newline else "")
    f = tmp_path_factory.mktemp("t") / "c.csv"
    f.write_bytes(text.encode("utf-8"))
    df, lines, errors, sep = read_tolerant_csv(f)
    expected = []
    for k, line in enumerate(text.splitlines()[1:], start=2):
        if line.strip():
            fields = next(csv.reader([line], skipinitialspace=True))
            while len(fields) > 4 and not fields[-1].strip():
                fields.pop()
            expected.append((k, (fields + [""] * 4)[:4], len(fields) != 4))
    assert sep == "," and lines.tolist() == [e[0] for e in expected]
    assert df.values.tolist() == [e[1] for e in expected]
    assert [bool(e) for e in errors] == [e[2] for e in expected]


def test_missing_columns_of_a_psychopy_file_suggest_the_mapping():
    from pathlib import Path

    f = Path(__file__).parent / "data" / "psychopy_height.csv"
    with pytest.raises(InputError, match=r"missing column\(s\) stimulus_id, x, y; .*e\.g\. x=mouse\.x,y=mouse\.y\)"):
        read_clicks(f)
