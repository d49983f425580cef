"""The optional compiled kernel of the exact rasteriser (issue 13).

Everything else is declared in pyproject.toml. The C file is plain C99,
loaded through ctypes (stimuli/render/kernel.py); if it does not build, the
install goes on and the renderer uses its numpy path.
"""

from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension(
            "stimuli.render.coverage_kernel",
            ["stimuli/render/coverage_kernel.c", "stimuli/render/coverage_bands.c"],
            depends=["stimuli/render/coverage_kernel.h"],
            extra_compile_args=["-O3", "-std=c99", "-fno-trapping-math"],
            optional=True,
        )
    ]
)
