"""Optional parts of nfdcal (installed as extras): a missing one is one clear line, not a traceback.

    distributed   nfdcal[dask]   sweeps on a Dask cluster (``nfdcal table --scheduler``)
"""
from __future__ import annotations

import importlib
from types import ModuleType


class MissingOptionalPart(RuntimeError):
    """An optional component that a requested feature needs is not installed."""


def require(module: str, extra: str, feature: str) -> ModuleType:
    """``module`` imported, or MissingOptionalPart naming the feature and the extra to install."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingOptionalPart(f"{feature} needs the Python package '{module}', which is not "
                                  f"installed: pip install 'nfdcal[{extra}]'") from None
