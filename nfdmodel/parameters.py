"""The import path of the vz and Walton-Braun parameter sets: each lives in its law's module.

``VZParams``, ``vz_largest_admissible_Kc`` and the admissible ``CA_HAT_RANGE``, ``KC_HAT_MAX``
(:mod:`nfdmodel.vz`: the Vu-Quoc & Zhang (1999) constants Ca [m/N], Kc [1/N] and their
admissibility), ``WaltonBraunParams`` (:mod:`nfdmodel.walton_braun`: K1 <= K2 [N/m], Walton & Braun
1986) and ``as_pair`` (:mod:`nfdmodel.materials`). A law's parameters are defined in its own module
(nfdmodel/README.md, Adding a law); this module lists no other law.
"""
from __future__ import annotations

from .materials import as_pair
from .vz import CA_HAT_RANGE, KC_HAT_MAX, VZParams, vz_largest_admissible_Kc
from .walton_braun import WaltonBraunParams

__all__ = ["CA_HAT_RANGE", "KC_HAT_MAX", "VZParams", "WaltonBraunParams", "as_pair", "vz_largest_admissible_Kc"]
