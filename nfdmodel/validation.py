"""The one number validator: a value becomes a finite float inside its allowed range, or a
ValueError naming the parameter and that range (the CLI prints it as one line, exit code 2)."""
from __future__ import annotations

import math
from numbers import Real

import numpy as np


def check_real(name: str, value, *, low: float | None = None, low_inclusive: bool = False,
               high: float | None = None, high_inclusive: bool = False, unit: str = "",
               text: bool = False) -> float:
    """Return ``value`` as a finite float, or raise ValueError naming ``name`` and its range.

    A string is a number only when ``text`` says the value was typed (a command-line flag);
    from the API a string is refused like any other non-number."""
    bounds = []
    if low is not None:
        bounds.append(f"{name} {'>=' if low_inclusive else '>'} {low:g}")
    if high is not None:
        bounds.append(f"{name} {'<=' if high_inclusive else '<'} {high:g}")
    allowed = " and ".join(bounds) if bounds else f"{name} finite"
    allowed += f" {unit}".rstrip() if unit else ""
    if isinstance(value, (bool, np.bool_)):        # float(True) == 1.0: never a silent number
        raise ValueError(f"{name} must be a number ({allowed}), got {value!r}")
    if isinstance(value, str) and not text:
        raise ValueError(f"{name} must be a number ({allowed}), got the text {value!r}")
    if not isinstance(value, (Real, np.number)):
        try:
            value = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a number ({allowed}), got {value!r}") from None
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite ({allowed}), got {value}")
    if low is not None and (value < low or (value == low and not low_inclusive)):
        raise ValueError(f"{name} out of range: need {allowed}, got {value:g}")
    if high is not None and (value > high or (value == high and not high_inclusive)):
        raise ValueError(f"{name} out of range: need {allowed}, got {value:g}")
    return value
