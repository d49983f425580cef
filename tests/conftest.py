"""Shared test set-up: fixtures used by several test modules.

``slow_generate.py`` is a script the batch tests run in a child process (it
slows every job so that the test can kill the run midway); it is not a test
module. Plain helper functions are in ``helpers.py``.
"""

import os
import shutil
from pathlib import Path

import pytest

from attneave.cli import main

from helpers import ARGS, CHROMIUM, PX_PER_DEG, SIZE_DEG, make_set, missing, with_timeout

collect_ignore = ["slow_generate.py", "helpers.py"]


@pytest.fixture(autouse=True)
def _no_progress_lines_by_the_clock(monkeypatch):
    """Commands announce stages that run over 2 s on stderr; on a loaded machine any stage may, and the tests
    that read stderr line by line would see lines that depend on the machine. The progress tests set their
    own threshold."""
    from attneave.stimuli import progress

    monkeypatch.setattr(progress, "THRESHOLD", float("inf"))


@pytest.fixture(scope="module")
def browser():
    why = missing()
    if why:
        if os.environ.get("ATTNEAVE_REQUIRE_BROWSER") == "1":
            pytest.fail(f"ATTNEAVE_REQUIRE_BROWSER=1 but {why}")
        pytest.skip(why)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        exe = CHROMIUM if os.path.exists(CHROMIUM) else shutil.which("chromium")
        b = p.chromium.launch(executable_path=exe, args=ARGS)
        # the page answers in milliseconds: a wait of seconds means a bug, not a slow machine
        b.new_context = with_timeout(b.new_context)
        b.new_page = with_timeout(b.new_page)
        yield b
        b.close()


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    """A set of 7 stimuli (3 items x peaks/troughs + a filler) and its experiment, 2 lists, 3 clicks each."""
    root = tmp_path_factory.mktemp("browser")
    shapes = make_set(root / "set")
    exp = root / "exp"
    assert main(["experiment", str(root / "set"), "-o", str(exp), "--lists", "2", "--clicks", "3",
                 "--px-per-deg", str(PX_PER_DEG), "--size-deg", str(SIZE_DEG), "--fixation-ms", "50",
                 "--iti-ms", "0", "--break-every", "2", "--seed", "test"]) == 0
    # the same without a fixed scale: the page calibrates (card) or takes ?px_per_mm=
    cal = root / "exp_cal"
    assert main(["experiment", str(root / "set"), "-o", str(cal), "--lists", "2", "--clicks", "3",
                 "--size-deg", str(SIZE_DEG), "--fixation-ms", "0", "--iti-ms", "0", "--seed", "test"]) == 0
    return dict(root=root, set=root / "set", exp=exp, cal=cal, shapes=shapes)


@pytest.fixture(scope="module")
def stimset(tmp_path_factory):
    d = tmp_path_factory.mktemp("set")
    make_set(d)
    return d


@pytest.fixture(scope="module")
def jspsych_npm():
    """node_modules of an npm prefix with jspsych@8 and two of its plugins (ATTNEAVE_JSPSYCH_DIR)."""
    d = os.environ.get("ATTNEAVE_JSPSYCH_DIR")
    why = None
    if not d:
        why = "ATTNEAVE_JSPSYCH_DIR is not set (npm install --prefix DIR jspsych@8 @jspsych/plugin-instructions " \
              "@jspsych/plugin-survey-text)"
    elif not (Path(d) / "node_modules/jspsych/dist/index.browser.js").is_file():
        why = f"ATTNEAVE_JSPSYCH_DIR={d} holds no node_modules/jspsych/dist/index.browser.js"
    if why:
        if os.environ.get("ATTNEAVE_REQUIRE_BROWSER") == "1":
            pytest.fail(f"ATTNEAVE_REQUIRE_BROWSER=1 but {why}")
        pytest.skip(why)
    return Path(d) / "node_modules"
