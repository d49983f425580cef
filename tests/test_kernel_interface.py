"""The compiled kernels' declared interface: C prototypes against the ctypes bindings.

Each kernel declares the functions Python calls in a header that its C
files include (so the compiler checks every definition against it), and
its kernel module declares the same functions for ctypes in
``SIGNATURES``. A signature changed on one side only would pass values of
the wrong type or number through ctypes (a crash or silent garbage); these
tests fail instead.
"""

from __future__ import annotations

import ctypes
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from attneave.stimuli import compiled
from attneave.stimuli.curves.qic import kernel as qic_kernel
from attneave.stimuli.render import kernel as render_kernel

#: (kernel module, header, C files, functions of the header that C calls and Python does not)
KERNELS = [
    (render_kernel, "coverage_api.h", ["coverage_kernel.c", "coverage_bands.c"], set()),
    (qic_kernel, "qic_api.h", ["qic_solve.c", "clothoid_moments.c"], {"attneave_moments"}),
]
C_TYPES = {"double": ctypes.c_double, "long": ctypes.c_long, "int": ctypes.c_int, "int64_t": ctypes.c_int64,
           "void": None}


def prototypes(header_text):
    """name -> (restype, [argtypes]) of every function prototype in a C header, as ctypes types."""
    text = re.sub(r"/\*.*?\*/", " ", header_text, flags=re.S)
    text = re.sub(r"(?m)^\s*#.*$", " ", text)
    out = {}
    for ret, name, args in re.findall(r"([A-Za-z_][\w\s\*]*?)\s*\b(\w+)\s*\(([^)]*)\)\s*;", text):
        out[name] = (_ctype(ret), [_ctype(re.sub(r"\w+$", "", a.strip()) if "*" not in a else a)
                                   for a in args.split(",") if a.strip() != "void"])
    return out


def _ctype(decl):
    if "*" in decl:
        return ctypes.c_void_p  # every pointer goes through ctypes as an address
    words = [w for w in decl.split() if w not in ("const", "unsigned", "signed")]
    return C_TYPES[words[-1]]


def test_the_prototype_reader_reads_types_and_pointers():
    got = prototypes("/* c */\n#include <x.h>\ndouble f(const double *x, long n,\n  int k);\nvoid g(void);")
    assert got == {"f": (ctypes.c_double, [ctypes.c_void_p, ctypes.c_long, ctypes.c_int]), "g": (None, [])}


@pytest.mark.parametrize("module, header, sources, internal", KERNELS, ids=["render", "qic"])
def test_every_binding_matches_its_c_prototype(module, header, sources, internal):
    folder = Path(module.__file__).resolve().parent
    declared = prototypes((folder / header).read_text())
    assert set(module.SIGNATURES) == set(declared) - internal
    for name, (restype, argtypes) in module.SIGNATURES.items():
        c_ret, c_args = declared[name]
        assert restype == c_ret, f"{name}: returns {c_ret} in {header}, {restype} in ctypes"
        assert list(argtypes) == c_args, f"{name}: arguments differ between {header} and {module.__name__}"


@pytest.mark.parametrize("module, header, sources, internal", KERNELS, ids=["render", "qic"])
def test_every_c_definition_agrees_with_its_header(module, header, sources, internal, tmp_path):
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler: the kernels are not built either")
    folder = Path(module.__file__).resolve().parent
    if not (folder / sources[0]).exists():
        pytest.skip("installed without the C sources")
    for src in sources:
        # a definition whose types differ from the header's prototype is a 'conflicting types' error
        proc = subprocess.run([cc, "-std=c99", "-fsyntax-only", "-Werror=implicit-function-declaration",
                               str(folder / src)], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr


def test_a_changed_signature_is_caught(tmp_path):
    header = (Path(render_kernel.__file__).resolve().parent / "coverage_api.h").read_text()
    changed = prototypes(header.replace("void attneave_integrate(double *acc, long rows, long cols)",
                                        "void attneave_integrate(double *acc, int rows, long cols)"))
    assert changed["attneave_integrate"][1] != render_kernel.SIGNATURES["attneave_integrate"][1]


@pytest.mark.parametrize("module, stem", [(render_kernel, "coverage_kernel"), (qic_kernel, "qic_solve")])
def test_the_status_says_which_path_runs_and_why(module, stem):
    status = compiled.STATUS[stem]
    assert status["path"] == module.KERNEL
    assert status["reason"]
    if module.KERNEL == "c":
        for name in module.SIGNATURES:  # every declared entry is exported by the build
            assert getattr(module.LIB, name).argtypes is not None


def test_the_expected_path_runs():
    """CI runs the kernel tests again on an install built with no C compiler (ATTNEAVE_EXPECT_KERNEL=numpy)."""
    import os

    expected = os.environ.get("ATTNEAVE_EXPECT_KERNEL")
    if not expected:
        pytest.skip("ATTNEAVE_EXPECT_KERNEL is not set")
    assert {render_kernel.KERNEL, qic_kernel.KERNEL} == {expected}
    if expected == "numpy":
        assert all("not built" in compiled.STATUS[s]["reason"] for s in ("coverage_kernel", "qic_solve"))
