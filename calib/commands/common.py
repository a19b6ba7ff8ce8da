"""Flags shared by sub-commands: numbers parsed with clear errors, and the material of a sphere.

Numbers are parsed inside ``run`` (not by argparse) so a bad value gives one line naming the
flag and its range from the dispatcher (exit code 2), never a traceback.
"""
from __future__ import annotations

# The paper's reference case (Vu-Quoc & Zhang 1999, section 2): aluminium sphere on a rigid flat.
MATERIAL_DEFAULTS = {"R": 0.1, "E": 70e9, "nu": 0.3, "sigma_y": 100e6, "rho": 2699.0}
MATERIAL_HELP = {"R": "sphere radius [m] (> 0)", "E": "Young's modulus [Pa] (> 0)",
                 "nu": "Poisson's ratio (0 <= nu < 0.5)", "sigma_y": "yield stress [Pa] (> 0)",
                 "rho": "density [kg/m^3] (> 0)"}


def number(flag: str, text, default=None) -> float:
    """``text`` as a finite float, or ``default`` when the flag was not given."""
    from nfdmodel import check_real

    return default if text is None else check_real(flag, text)


def add_material_arguments(parser) -> None:
    """--R --E --nu --sigma-y --rho, defaulting to the reference aluminium sphere."""
    for key, help_text in MATERIAL_HELP.items():
        parser.add_argument(f"--{key.replace('_', '-')}", dest=key, default=None,
                            help=f"{help_text} (default {MATERIAL_DEFAULTS[key]:g})")


def material_flags(ns) -> dict:
    """The material flags the user gave (None for those left at their default)."""
    return {key: getattr(ns, key) for key in MATERIAL_DEFAULTS}


def material_from_args(ns):
    """(nfdmodel.Material, R [m]) from the namespace; validation names the parameter and range."""
    from nfdmodel import Material

    values = {key: number(f"--{key.replace('_', '-')}", text, MATERIAL_DEFAULTS[key])
              for key, text in material_flags(ns).items()}
    material = Material(values["E"], values["nu"], values["sigma_y"], values["rho"])
    if not values["R"] > 0:
        raise ValueError(f"--R out of range: need R > 0 m, got {values['R']:g}")
    return material, values["R"]


def is_reference(ns) -> bool:
    """True when no material flag differs from the reference case."""
    return all(text is None or number(f"--{k}", text) == MATERIAL_DEFAULTS[k]
               for k, text in material_flags(ns).items())
