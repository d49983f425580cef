"""What every benchmark prints first: the machine and the library stack.

Figures measured on a loaded or different machine are not comparable; the
CPU model, core count, load average and library versions printed with each
run say which machine and stack a figure belongs to.
"""

from __future__ import annotations

import os
import platform
import statistics
import time
from importlib import metadata

_PACKAGES = ("numpy", "scipy", "opencv-contrib-python-headless", "scikit-image", "pandas",
             "matplotlib", "shapely", "pydantic")


def cpu_model():
    """The CPU model name from /proc/cpuinfo (or the platform's guess)."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def versions(packages=_PACKAGES):
    """Installed versions of `packages` as ``name=version`` strings."""
    out = []
    for name in packages:
        try:
            out.append(f"{name}={metadata.version(name)}")
        except metadata.PackageNotFoundError:
            out.append(f"{name}=absent")
    return out


def load():
    """The 1-minute load average, or NaN where the OS has none."""
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


def header(title, packages=_PACKAGES):
    """Print the benchmark's title, the machine, its load and the stack."""
    print(f"== {title}")
    print(f"machine: {cpu_model()}; {os.cpu_count()} cpus; load average {load():.2f}; "
          f"Python {platform.python_version()}")
    print("stack: " + ", ".join(versions(packages)))


def median_time(fn, repeats):
    """Median wall time of `repeats` calls of `fn` (seconds), never the best."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)
