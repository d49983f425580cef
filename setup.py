"""The package layout and the optional compiled kernels.

One import name is installed, ``attneave``: its entrance lives in
``src/attneave`` (the src layout, so that the repository's root never shadows
the installed package), and the two libraries keep the repository's
top-level folders, mapped into the namespace with ``package_dir``::

    src/attneave -> attneave
    stimuli/     -> attneave.stimuli
    analysis/    -> attneave.analysis

The C kernels are plain C99, loaded through ctypes
(``stimuli/render/kernel.py``, ``stimuli/curves/qic/kernel.py``) with their
prototypes checked against the headers by ``tests/test_kernel_interface.py``;
if one does not build (no compiler), the install goes on and the numpy path
is used (``attneave info`` says which and why).

Everything else is declared in pyproject.toml.
"""

import sys

from setuptools import Extension, find_packages, setup

FLAGS = ["-O3", "-std=c99", "-fno-trapping-math"]
ROOTS = {"attneave": "src/attneave", "attneave.stimuli": "stimuli", "attneave.analysis": "analysis"}


def packages():
    out = []
    for name, folder in ROOTS.items():
        out.append(name)
        out += [f"{name}.{sub}" for sub in find_packages(folder)]
    return out


setup(
    package_dir=ROOTS,
    packages=packages(),
    ext_modules=[
        Extension("attneave.stimuli.render.coverage_kernel",
                  ["stimuli/render/coverage_kernel.c", "stimuli/render/coverage_bands.c"],
                  depends=["stimuli/render/coverage_kernel.h"], extra_compile_args=FLAGS, optional=True),
        # sin, cos, atan2: libm, which Windows has in its C runtime
        Extension("attneave.stimuli.curves.qic.qic_solve",
                  ["stimuli/curves/qic/qic_solve.c", "stimuli/curves/qic/clothoid_moments.c"],
                  extra_compile_args=FLAGS,
                  libraries=[] if sys.platform == "win32" else ["m"], optional=True),
    ],
)
