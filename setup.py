"""Build of the optional compiled kernel (nfdmodel._native: nfdmodel/nfd_kernel.c and its binding).

Everything else is declared in pyproject.toml. ``optional=True``: without a C compiler (or the
Python headers) the build of the extension is skipped with a warning, the install succeeds and
nfdmodel runs on its numpy kernels (nfdmodel.backend() says "numpy" and why). -fno-math-errno
lets sqrt vectorise (errno is never read); -ffp-contract=off keeps a*b + c two roundings, as
numpy computes it, even where CFLAGS ask for a CPU with fused multiply-add.
"""
from setuptools import Extension, setup

setup(ext_modules=[Extension("nfdmodel._native", sources=["nfdmodel/_native.c", "nfdmodel/nfd_kernel.c"],
                             extra_compile_args=["-std=c99", "-O3", "-fno-math-errno", "-ffp-contract=off"], optional=True)])
