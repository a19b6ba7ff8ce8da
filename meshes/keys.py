"""Cache keys that survive library upgrades.

A finished result is found again by a hash of what determines it. Computed inputs (mesh sizes
from the contact radius, the yield point from A_Y(nu)'s bounded search) can change in their last
digit with a new numpy or scipy; hashed as they are, every finished result would then look
unfinished. So every float is rounded to KEY_DIGITS significant digits before hashing: far below
any tolerance of the FE (1e-10) and far above round-off (1e-16).
"""
from __future__ import annotations

import hashlib
import json
import math

KEY_DIGITS = 12


def canonical(value):
    """``value`` with every float rounded to KEY_DIGITS significant digits (recursively through
    dicts, lists and tuples; tuples become lists, as JSON has them)."""
    if isinstance(value, bool) or value is None or isinstance(value, (int, str)):
        return value
    if isinstance(value, float):
        return float(f"{value:.{KEY_DIGITS}g}") if math.isfinite(value) else repr(value)
    if isinstance(value, dict):
        return {str(k): canonical(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [canonical(v) for v in value]
    raise TypeError(f"cannot key a {type(value).__name__}")


def stable_key(payload, length: int = 16) -> str:
    """Hex digest (``length`` characters) of the canonical JSON of ``payload``."""
    text = json.dumps(canonical(payload), sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:length]
