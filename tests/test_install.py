"""Installing attneave beside other packages: one import name, nothing overwritten.

A wheel of this checkout is built and installed into a fresh virtual
environment that already holds PyPI's ``stimuli`` 1.2.0 (an auditory-stimuli
package a perception lab may well have): attneave must leave that package's
files as they were, install nothing at the top of site-packages but
``attneave`` and its dist-info, and work from a folder holding a user's own
``analysis.py`` and ``stimuli/``. A second wheel is built with no C compiler:
it must install, run on the numpy path, and say so in ``attneave info``.

The wheel of ``stimuli`` comes from ``ATTNEAVE_STIMULI_WHEELS`` (a folder,
as ``.ci/run`` downloads it) or from PyPI; without either the test is skipped,
unless ``ATTNEAVE_REQUIRE_INSTALL_TEST=1`` (CI) turns the skip into a failure.
"""

from __future__ import annotations

import base64
import csv
import hashlib
import json
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


def _skip(why):
    if os.environ.get("ATTNEAVE_REQUIRE_INSTALL_TEST") == "1":
        pytest.fail(f"ATTNEAVE_REQUIRE_INSTALL_TEST=1 but {why}")
    pytest.skip(why)


def _run(cmd, **kwargs):
    proc = subprocess.run(cmd, capture_output=True, text=True, **kwargs)
    assert proc.returncode == 0, f"{cmd}: {proc.stdout[-2000:]}{proc.stderr[-2000:]}"
    return proc.stdout


@pytest.fixture(scope="module")
def stimuli_wheel(tmp_path_factory):
    folder = os.environ.get("ATTNEAVE_STIMULI_WHEELS")
    if not folder:
        folder = tmp_path_factory.mktemp("stimuli_wheel")
        proc = subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", "-q", "-d", str(folder),
                               "stimuli==1.2.0"], capture_output=True, text=True)
        if proc.returncode:
            _skip("PyPI's stimuli 1.2.0 cannot be downloaded (no network) and ATTNEAVE_STIMULI_WHEELS is not set")
    wheels = sorted(Path(folder).glob("stimuli-1.2.0-*.whl"))
    if not wheels:
        _skip(f"no stimuli-1.2.0 wheel in {folder}")
    return wheels[0]


def _wheel(out, env=None):
    """A wheel built from a copy of the checkout's sources (an editable install leaves the kernels built in
    place and setuptools a build/ folder: neither may leak into this wheel), with this environment's
    setuptools (no download)."""
    src = Path(out) / "src"
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(
        "*.so", "*.pyd", "build", "*.egg-info", ".git", ".venv", "out", "__pycache__", ".pytest_cache"))
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(out), str(src)],
         env=env)
    return next(Path(out).glob("attneave-*.whl"))


@pytest.fixture(scope="module")
def venv(tmp_path_factory, stimuli_wheel):
    """A fresh environment with stimuli 1.2.0, then attneave's wheel; attneave's dependencies come from
    this test's own environment through a path entry (no download, no .pth processing of its site)."""
    root = tmp_path_factory.mktemp("install")
    env_dir = root / "env"
    _run([sys.executable, "-m", "venv", "--without-pip", str(env_dir)])
    py = env_dir / "bin" / "python"
    site = Path(_run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"]).strip())
    (site / "zz_test_dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    pip = [sys.executable, "-m", "pip", "--python", str(py)] if _pip_has_python_option() else None
    if pip is None:
        _skip("pip is too old for --python")
    _run([*pip, "install", "--no-deps", "--no-index", "-q", str(stimuli_wheel)])
    record_before = _hashes(site, "stimuli-1.2.0.dist-info")
    wheel = _wheel(root / "wheel")
    _run([*pip, "install", "--no-deps", "--no-index", "-q", str(wheel)])
    return dict(root=root, env=env_dir, py=py, site=site, wheel=wheel, pip=pip, record_before=record_before)


def _pip_has_python_option():
    return "--python" in subprocess.run([sys.executable, "-m", "pip", "--help"], capture_output=True, text=True).stdout


def _hashes(site, dist_info):
    """The files of a distribution and whether each still has its RECORD hash."""
    out = {}
    with open(site / dist_info / "RECORD", newline="") as f:
        for path, digest, _ in csv.reader(f):
            if digest.startswith("sha256=") and (site / path).exists():
                h = base64.urlsafe_b64encode(hashlib.sha256((site / path).read_bytes()).digest()).rstrip(b"=")
                out[path] = h.decode() == digest[7:]
            elif digest:
                out[path] = False
    return out


def test_the_auditory_stimuli_package_is_left_as_it_was(venv):
    after = _hashes(venv["site"], "stimuli-1.2.0.dist-info")
    assert after == venv["record_before"] and all(after.values())
    # which 'stimuli' an import finds (running its __init__ would need its audio dependencies, e.g. sounddevice
    # and PortAudio, which this test does not install)
    code = "import importlib.util as u; print(u.find_spec('stimuli').origin)"
    origin = Path(_run([str(venv["py"]), "-c", code], cwd=venv["root"]).strip())
    assert origin == venv["site"] / "stimuli" / "__init__.py" and (origin.parent / "audio" / "tone.py").exists()


def test_attneave_installs_one_name_at_the_top_of_site_packages(venv):
    with zipfile.ZipFile(venv["wheel"]) as z:
        top = {name.split("/")[0] for name in z.namelist()}
    assert top == {"attneave", venv["wheel"].name.split("-")[0] + "-" + venv["wheel"].name.split("-")[1]
                   + ".dist-info"}
    installed = {line.split(",")[0].split("/")[0] for line in
                 (next(venv["site"].glob("attneave-*.dist-info")) / "RECORD").read_text().splitlines()}
    assert {t for t in installed if t != ".."} == top  # '..' is the console script in bin/


def test_attneave_works_beside_a_users_analysis_and_stimuli_folders(venv, tmp_path):
    work = tmp_path / "project"
    (work / "stimuli").mkdir(parents=True)
    (work / "stimuli" / "__init__.py").write_text("MINE = True\n")
    (work / "analysis.py").write_text("MINE = True\n")
    code = ("import sys; sys.path.insert(0, '');"  # as 'python' in that folder, interactive or a notebook, has it
            "import attneave, attneave.analysis.analyze, attneave.stimuli.geometry.contour, analysis, stimuli;"
            "import json; print(json.dumps([attneave.__file__, analysis.MINE, stimuli.MINE]))")
    out = json.loads(_run([str(venv["py"]), "-c", code], cwd=work))
    assert out[0].startswith(str(venv["site"])) and out[1:] == [True, True]
    helptext = _run([str(venv["env"] / "bin" / "attneave"), "--help"], cwd=work)
    assert "surprisal" in helptext and "analyze" in helptext
    # a command end to end from that folder
    (work / "c.csv").write_text("x,y\n0,0\n10,0\n10,10\n0,10\n")
    _run([str(venv["env"] / "bin" / "attneave"), "surprisal", "c.csv", "-o", "s.csv", "-n", "40"], cwd=work)
    assert (work / "s.csv").read_text().count("\n") == 41


def test_without_a_c_compiler_the_install_succeeds_on_the_numpy_path_and_says_so(venv, tmp_path):
    env = dict(os.environ, CC="false", LDSHARED="false")  # every compile fails, as on a machine without one
    wheel = _wheel(tmp_path / "wheel", env=env)
    with zipfile.ZipFile(wheel) as z:
        assert not [n for n in z.namelist() if n.endswith((".so", ".pyd"))]
    target = tmp_path / "site"
    _run([*venv["pip"], "install", "--no-deps", "--no-index", "-q", "--target", str(target), str(wheel)])
    code = "import json, attneave.info; print(json.dumps(attneave.info.kernel_status()))"
    status = json.loads(_run([str(venv["py"]), "-c", code], cwd=tmp_path, env=dict(os.environ, PYTHONPATH=str(target))))
    for k in status.values():
        assert k["path"] == "numpy" and "not built" in k["reason"]
