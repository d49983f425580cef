"""--jatos: the page submits through jatos.js, and a .jzip study archive JATOS imports.

The browser tests run the page against a stand-in ``jatos.js`` (written
here) that implements the documented calls (``jatos.onLoad``,
``jatos.submitResultData`` returning a promise, ``jatos.endStudy``,
``jatos.endStudyAndRedirect``, ``jatos.urlQueryParameters``,
``jatos.componentJsonInput``) and records them.
"""

import io
import json
import urllib.parse
import zipfile

import pandas as pd
import pytest

from attneave.cli import main

from helpers import client_xy, make_set, target_points, write_jatos_stand_in


def serve(page, exp):
    def handle(route):
        path = urllib.parse.urlparse(route.request.url).path
        f = exp / path.lstrip("/")
        route.fulfill(path=str(f)) if f.is_file() else route.fulfill(status=404)
    page.route("http://attneave.test/**", handle)


@pytest.fixture(scope="module")
def shapes(tmp_path_factory):
    d = tmp_path_factory.mktemp("set")
    return d, make_set(d)


@pytest.fixture(scope="module")
def stimset(shapes):
    return shapes[0]


@pytest.fixture(scope="module")
def jatos_exp(tmp_path_factory, stimset):
    exp = tmp_path_factory.mktemp("jatos") / "my study"
    assert main(["experiment", str(stimset), "-o", str(exp), "--jatos", "--clicks", "2", "--size-px", "320",
                 "--fixation-ms", "0", "--iti-ms", "0", "--order", "fixed", "--conditions", "peaks",
                 "--participant-param", "prolific"]) == 0
    return exp


def test_jzip_unpacks_to_the_documented_layout(jatos_exp):
    jzips = sorted(jatos_exp.glob("*.jzip"))
    assert [p.name for p in jzips] == ["attneave_my_study.jzip"]
    with zipfile.ZipFile(jzips[0]) as z:
        names = z.namelist()
        jas = json.loads(z.read("attneave_my_study.jas"))
        index = z.read("attneave_my_study/index.html").decode()
    # JATOS's JZIP: the .jas study properties at the top, the assets folder named by dirName beside it
    tops = {n.split("/")[0] for n in names}
    assert tops == {"attneave_my_study.jas", "attneave_my_study"}
    assert jas["version"] == "3"
    data = jas["data"]
    assert {"uuid", "title", "dirName", "componentList"} <= set(data)
    assert data["dirName"] == "attneave_my_study"
    (component,) = data["componentList"]
    assert {"uuid", "title", "htmlFilePath"} <= set(component)
    assert f"attneave_my_study/{component['htmlFilePath']}" in names
    assert json.loads(component["jsonData"]) == {"completion_url": None}
    assert '<script src="jatos.js"></script>' in index
    # every file of the experiment (the images too) is among the assets; jatos.js is JATOS's own
    for f in ("task.js", "task.css", "images/a_peaks.png", "images/c_peaks.png"):
        assert f"attneave_my_study/{f}" in names
    assert (jatos_exp / "images" / "a_peaks.png").read_bytes() == zipfile.ZipFile(jzips[0]).read(
        "attneave_my_study/images/a_peaks.png")
    assert not any(n.endswith("jatos.js") or n.endswith(".jzip") for n in names)


def test_the_same_folder_name_gives_the_same_study_uuid(tmp_path, stimset):
    # a rebuilt experiment updates the study JATOS has instead of adding a copy
    uuids = []
    for k in range(2):
        exp = tmp_path / f"run{k}" / "exp"
        exp.parent.mkdir()
        assert main(["experiment", str(stimset), "-o", str(exp), "--jatos", "--title", f"T{k}"]) == 0
        with zipfile.ZipFile(exp / "attneave_exp.jzip") as z:
            uuids.append(json.loads(z.read("attneave_exp.jas"))["data"]["uuid"])
    assert uuids[0] == uuids[1]


def test_jatos_with_submit_url_is_refused(tmp_path, stimset, capsys):
    assert main(["experiment", str(stimset), "-o", str(tmp_path / "e"), "--jatos", "--submit-url", "/x"]) == 2
    assert "submit-url" in capsys.readouterr().err


@pytest.mark.parametrize("completion", [None, "https://app.prolific.com/submissions/complete?cc=C0DE"])
def test_page_submits_through_jatos_then_ends_the_study(browser, jatos_exp, shapes, completion):
    pid = "60a1b2c3d4e5f6a7b8c9d0e1"
    write_jatos_stand_in(jatos_exp, {"PROLIFIC_PID": pid, "STUDY_ID": "S1", "SESSION_ID": "SE1"},
                   {"completion_url": completion} if completion else {})
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    serve(page, jatos_exp)
    page.goto("http://attneave.test/index.html")        # no id in the component's own address
    page.click("#next")                                 # instructions
    shapes_seen = []
    for _ in range(3):
        page.wait_for_selector("#frame:not([hidden]) #stimulus[data-stimulus-id]")
        sid = page.get_attribute("#stimulus", "data-stimulus-id")
        shapes_seen.append(sid)
        for p in target_points(shapes[1], sid)[:2]:
            page.mouse.click(*client_xy(page, p)[:2])
        page.click("#next")
    page.wait_for_selector("#submit-status[data-state=ok]", timeout=20000)
    calls = page.evaluate("window.jatosCalls")
    rows = page.evaluate("window.attneaveData")
    download = page.query_selector("#download")
    page.close()

    names = [c[0] for c in calls]
    assert names[0] == "onLoad" and names.count("submitResultData") == 2   # one failure, one retry
    ends = [c for c in calls if c[0].startswith("endStudy")]
    assert len(ends) == 1 and names.index(ends[0][0]) > names.index("submitResultData")
    if completion:
        assert ends[0] == ["endStudyAndRedirect", completion]
    else:
        assert ends[0] == ["endStudy"]
    assert download is None                              # no download: the data went to JATOS
    submitted = pd.read_csv(io.StringIO(calls[-2][1]), dtype=str, keep_default_na=False)
    expected = pd.DataFrame(rows)
    assert len(submitted) == len(rows) == 6
    for col in ("participant", "stimulus_id", "STUDY_ID", "SESSION_ID"):
        assert submitted[col].tolist() == expected[col].tolist(), col
    for col in ("x", "y", "click", "trial"):
        assert submitted[col].astype(float).tolist() == expected[col].astype(float).tolist(), col
    assert set(submitted.participant) == {pid} and set(submitted.STUDY_ID) == {"S1"}
    assert shapes_seen == ["a_peaks", "b_peaks", "c_peaks"]
