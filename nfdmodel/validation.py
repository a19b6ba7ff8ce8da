"""The one number validator: a value becomes a finite float inside its allowed range, or a
ValueError naming the parameter and that range (the CLI prints it as one line, exit code 2)."""
from __future__ import annotations

import math
import re
from numbers import Real

import numpy as np

from . import limits


# What a person means by a number: digits with an optional point and exponent (Python's float()
# also reads "0_05" as 5 and "1_000" as 1000); inf and nan are read to be named as not finite.
_NUMBER_TEXT = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|[-+]?(inf|infinity|nan)", re.IGNORECASE)


def number_from_text(name: str, text: str, allowed: str = "") -> float:
    """The float a typed number means, or ValueError naming ``name``: digits, one optional point,
    an optional exponent (surrounding blanks ignored); no underscores, no hexadecimal."""
    if not _NUMBER_TEXT.fullmatch(text.strip()):
        what = f" ({allowed})" if allowed else ""
        hint = "; digits only, no '_' (0_05 is not 0.05)" if "_" in text else ""
        raise ValueError(f"{name} must be a number{what}, got {text!r}{hint}")
    return float(text)


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
    if isinstance(value, str):
        value = number_from_text(name, value, allowed)
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


# The range of real solids and impacts (SI; the bounds are nfd_limits.h's). A value outside is a
# unit slip, not a material: it is refused with the likely slip named. Values inside but unusual
# for a DEM particle get a PlausibilityWarning that names the slip they would be.
SOLID_RANGES = {
    "E": (limits.E_MIN, limits.E_MAX, "Pa", "Young's modulus of solids: gels 1e5 Pa .. diamond 1.2e12 Pa"),
    "sigma_y": (limits.SIGMA_Y_MIN, limits.SIGMA_Y_MAX, "Pa",
                "yield stress of solids: soft foams 1e4 Pa .. whiskers 1e11 Pa"),
    "rho": (limits.RHO_MIN, limits.RHO_MAX, "kg/m^3", "density of solids: aerogels 10 .. osmium 22,590 kg/m^3"),
    "v_in": (0.0, limits.V_IN_MAX, "m/s", "impact velocity a contact law describes (hypervelocity above)"),
}
# (factor, unit typed instead): "did you give GPa?" when value x factor falls inside the range
UNIT_SLIPS = {"E": ((1e9, "GPa"), (1e6, "MPa")), "sigma_y": ((1e6, "MPa"), (1e3, "kPa")),
              "rho": ((1e3, "g/cm^3"),), "v_in": ((1e-3, "mm/s"),), "R": ((1e-3, "mm"), (1e-2, "cm"))}
LARGEST_USUAL_RADIUS = limits.RADIUS_USUAL_MAX   # [m]: DEM particles above it are unusual (a boulder): warned
LARGEST_POSSIBLE_RADIUS = limits.RADIUS_MAX      # [m]: no particle of a contact model is larger: refused


class PlausibilityWarning(UserWarning):
    """A value possible for a solid but unusual for a DEM particle, and what unit slip it would be."""


def unit_slip(name: str, value: float) -> str:
    """'; did you give GPa? 70 GPa = 7e+10 Pa' when ``value`` x a slip factor is a usual value."""
    low, high = SOLID_RANGES[name][:2] if name in SOLID_RANGES else (1e-7, LARGEST_USUAL_RADIUS)
    unit = SOLID_RANGES[name][2] if name in SOLID_RANGES else "m"
    for factor, typed in UNIT_SLIPS.get(name, ()):
        if low <= value * factor <= high and value * factor != value:
            return f"; did you give {typed}? {value:g} {typed} = {value * factor:g} {unit}"
    return ""


def check_solid(name: str, value: float, label: str | None = None) -> float:
    """``value`` (already a finite float) inside the range of real solids for the quantity ``name``
    (a key of SOLID_RANGES), or ValueError naming the parameter (``label``, default ``name``), the
    range and the likely unit slip."""
    low, high, unit, what = SOLID_RANGES[name]
    if not low <= value <= high:
        kind = "an impact" if name == "v_in" else "a solid"
        label = label or name
        raise ValueError(f"{label} out of range for {kind}: need {low:g} <= {label} <= {high:g} {unit} "
                         f"({what}), got {value:g}{unit_slip(name, value)}")
    return value


def bound_text(value: float, side: str, digits: int = 4) -> str:
    """``value`` as a printed bound of ``digits`` significant digits, rounded into the admissible
    side: ``side`` "<=" (an upper bound) rounds down, ">=" (a lower bound) rounds up, so that a
    suggestion a refusal prints ("need v_max <= 0.2195 m/s") is accepted when followed."""
    if side not in ("<=", ">="):
        raise ValueError(f"side must be '<=' or '>=', got {side!r}")
    value = float(value)
    text = f"{value:.{digits}g}"
    if not math.isfinite(value) or value == 0.0:
        return text
    scale = 10.0 ** (math.floor(math.log10(abs(value))) - digits + 1)
    for _ in range(4):          # one ulp of the last digit at a time until it lies inside
        printed = float(text)
        if (printed <= value) if side == "<=" else (printed >= value):
            return text
        step = -scale if side == "<=" else scale
        text = f"{printed + step:.{digits}g}"
    return text
