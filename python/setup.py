"""Builds and installs the motionbus Python package from the library's headers, offline, with
Debian's setuptools and pybind11 (docs/python.md):

    /usr/bin/python3 -m pip install --no-build-isolation --no-index ./python
"""

import glob
import os
import re

from pybind11.setup_helpers import ParallelCompile, Pybind11Extension, build_ext
from setuptools import setup

HERE = os.path.dirname(os.path.abspath(__file__))
INCLUDE = os.path.join(os.path.dirname(HERE), "include")


def version() -> str:
    with open(os.path.join(INCLUDE, "motionbus", "version.hpp"), encoding="utf-8") as f:
        text = f.read()
    parts = [re.search(rf"#define MOTIONBUS_VERSION_{p} (\d+)", text).group(1)  # type: ignore[union-attr]
             for p in ("MAJOR", "MINOR", "PATCH")]
    return ".".join(parts)


ParallelCompile("MOTIONBUS_BUILD_JOBS", default=2).install()
os.chdir(HERE)  # setuptools wants the sources relative to this file
setup(
    name="motionbus",
    version=version(),
    description="T-format, Modbus and BiSS-C codecs from the motionbus C++ headers",
    packages=["motionbus", "motionbus.devices"],
    package_data={"motionbus": ["*.pyi", "py.typed"], "motionbus.devices": ["*.pyi"]},
    ext_modules=[Pybind11Extension("motionbus._motionbus", sorted(glob.glob("src/*.cpp")),
                                   include_dirs=[INCLUDE], cxx_std=17)],
    cmdclass={"build_ext": build_ext},
    zip_safe=False,
    python_requires=">=3.8",
)
