"""The optional compiled kernels: the exact rasteriser's (issue 13) and the
pure G2 QIC spline's solve (issue 9).

Everything else is declared in pyproject.toml. The C files are plain C99,
loaded through ctypes (stimuli/render/kernel.py, stimuli/curves/qic_kernel.py);
if one does not build, the install goes on and its numpy path is used.
"""

import sys

from setuptools import Extension, setup

FLAGS = ["-O3", "-std=c99", "-fno-trapping-math"]

setup(
    ext_modules=[
        Extension("stimuli.render.coverage_kernel",
                  ["stimuli/render/coverage_kernel.c", "stimuli/render/coverage_bands.c"],
                  depends=["stimuli/render/coverage_kernel.h"], extra_compile_args=FLAGS, optional=True),
        # sin, cos, atan2: libm, which Windows has in its C runtime
        Extension("stimuli.curves.qic_solve", ["stimuli/curves/qic_solve.c", "stimuli/curves/clothoid_moments.c"],
                  extra_compile_args=FLAGS,
                  libraries=[] if sys.platform == "win32" else ["m"], optional=True),
    ]
)
