"""The one compiled part of the project: the self-contained FMU's binary (fmu/native, C99/C11).

``pip install`` builds it with the Python's C compiler as ``fmu/_vc_fmi*.so``; ``vc fmu export``
copies it into each FMU as ``binaries/linux64/<model>.so``.  It is no Python extension module (it
never links libpython and is never imported): it only travels with the package.  Without a C
compiler the installation still succeeds (the extension is optional) and ``vc fmu export`` says
what is missing; ``vc fmu export --python host`` (the lean FMU) needs no compiler.
"""

import sys

from setuptools import Extension, setup

NATIVE = "fmu/native"

native = [Extension(
    "fmu._vc_fmi",
    sources=[f"{NATIVE}/worker_link.c", f"{NATIVE}/fmi2.c", f"{NATIVE}/fmi3.c"],
    include_dirs=[NATIVE, f"{NATIVE}/include"],
    # only the FMI functions are exported (FMI2_Export / FMI3_Export); glibc 2.17 is the floor
    extra_compile_args=["-std=c11", "-fvisibility=hidden", "-Wall", "-Wextra", "-Werror"],
    optional=True,
)] if sys.platform.startswith("linux") else []

setup(ext_modules=native)
