"""The short public API of ``import attneave``: every name resolves, cheaply.

A lazy entrance that names a moved module fails only when a user touches
the name; these tests touch every one.
"""

import subprocess
import sys

import pytest

import attneave


@pytest.mark.parametrize("name", attneave.__all__)
def test_every_public_name_resolves(name):
    value = getattr(attneave, name)
    assert value is not None
    assert name in dir(attneave)


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'nothing_here'"):
        attneave.nothing_here  # noqa: B018


def test_one_version_everywhere():
    from importlib.metadata import version

    from attneave.stimuli import __version__

    assert attneave.__version__ == __version__ == version("attneave")
    out = subprocess.run([sys.executable, "-m", "attneave", "--version"], capture_output=True, text=True).stdout
    assert out.strip() == f"attneave {__version__}"


def test_import_attneave_loads_no_heavy_library():
    code = ("import sys, attneave; heavy = {'numpy', 'scipy', 'cv2', 'pandas', 'matplotlib', 'pydantic'};"
            "print(sorted(heavy & set(sys.modules)))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
