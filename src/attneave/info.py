"""``attneave info``: what this installation runs on.

The version, Python and the core libraries, which path each compiled kernel
takes (the C kernel or its numpy reference, 2-3x slower) and why, and which
optional extras are installed. An install without a C compiler succeeds on
the numpy path; this is where a user sees it.
"""

from __future__ import annotations

import importlib

__all__ = ["kernel_status", "installation", "add_parser", "run"]

#: kernel -> (module that loads it, what it speeds up)
KERNELS = {
    "coverage_kernel": ("attneave.stimuli.render.kernel", "exact-coverage rasteriser (generate, render)"),
    "qic_solve": ("attneave.stimuli.curves.qic.kernel", "QIC spline solve and sampling (spline, curves)"),
}
#: optional extra -> the modules it brings
EXTRAS = {"dask": "distributed", "model": "onnxruntime", "rembg": "rembg", "browser tests": "playwright"}


def kernel_status():
    """Which path each compiled kernel takes, and why.

    Returns
    -------
    dict
        Kernel name -> ``{"path": 'c' or 'numpy', "reason": str, "file": str
        or None, "used_by": str}``.

    Examples
    --------
    >>> status = kernel_status()
    >>> sorted(status)
    ['coverage_kernel', 'qic_solve']
    >>> status["qic_solve"]["path"] in ("c", "numpy")
    True
    """
    from attneave.stimuli.compiled import STATUS

    out = {}
    for name, (module, used_by) in KERNELS.items():
        importlib.import_module(module)  # loading records the outcome
        out[name] = dict(STATUS[name], used_by=used_by)
    return out


def _version(dist):
    import importlib.metadata  # here, not at the top: `attneave --help` imports this module

    try:
        return importlib.metadata.version(dist)
    except importlib.metadata.PackageNotFoundError:
        return None


def installation():
    """Versions, kernels and optional extras of this installation, as a dict."""
    import importlib.util
    import platform

    from attneave import __version__

    core = {name: _version(dist) for name, dist in [
        ("numpy", "numpy"), ("scipy", "scipy"), ("pandas", "pandas"), ("scikit-image", "scikit-image"),
        ("opencv", "opencv-contrib-python-headless"), ("matplotlib", "matplotlib"), ("pydantic", "pydantic")]}
    extras = {}
    for extra, module in EXTRAS.items():
        extras[extra] = importlib.util.find_spec(module) is not None
    return {"attneave": __version__, "python": platform.python_version(), "platform": platform.platform(),
            "libraries": core, "kernels": kernel_status(), "extras": extras}


def add_parser(sub):
    from attneave.stimuli.commands.examples import ExamplesFormatter

    p = sub.add_parser(
        "info", help="versions, compiled kernels (C or numpy, and why) and optional extras",
        description=__doc__.split("\n\n")[1].replace("\n", " "),
        epilog="examples:\n  attneave info\n  attneave info --json > install.json",
        formatter_class=ExamplesFormatter)  # the description wrapped, the examples as written
    p.add_argument("--json", action="store_true", help="print the information as JSON")
    return p


def run(args):
    import json

    info = installation()
    if args.json:
        print(json.dumps(info, indent=2))
        return 0
    print(f"attneave {info['attneave']} on Python {info['python']} ({info['platform']})")
    print("libraries: " + ", ".join(f"{k} {v}" for k, v in info["libraries"].items() if v))
    for name, k in info["kernels"].items():
        path = "compiled C" if k["path"] == "c" else "numpy (2-3x slower)"
        print(f"kernel {name}: {path}: {k['reason']} [{k['used_by']}]")
    print("extras: " + ", ".join(f"{k} {'yes' if v else 'no'}" for k, v in info["extras"].items()))
    return 0
