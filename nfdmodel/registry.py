"""The laws by name: ``get_law("hertz" | "vz" | "vz-table" | "thornton" | "walton-braun" | "vz-unload") -> ContactLaw``.

Each law module declares its :class:`ContactLaw` as ``LAW`` next to its kernel
(:mod:`nfdmodel.contact_law` says what a ContactLaw does: ``step``, ``commit``, ``force``, the
energies and radii); this module lists them. In a DEM loop that owns its history,
``P, update = law.step(delta, state, params); law.commit(state, update)`` avoids copying the
n-contact history whenever one contact loads plastically.

``delta`` is the total approach ("overlap") of each contact [m], shape (n,), any float dtype;
``state`` the named per-contact history; ``P`` the normal force [N], float64, >= 0.

Adding a law ``new`` (Python side): ``nfdmodel/new.py`` (its history class, a TurningPointHistory
subclass; its parameters; the virgin-curve loading branch of nfdmodel.turning_point; ``new_step``,
``new_force`` and ``LAW = ContactLaw(...)``), one entry in ``LAWS`` below, and its scalar step in
``nfdmodel/reference.py`` (the specification the kernels are tested against). A compiled kernel
adds ``NFD_LAW_NEW`` to ``nfd_limits.h`` (limits.LAW_CODES follows) and the law to
``nfd_kernel.{h,c}``; the law module then calls ``native.law_loading("new", ...)`` and states
``collision_params``. tests/test_limits.py checks that ``LAWS``, the codes of nfd_limits.h, the cases of
the kernel's ``nfd_step`` and the LAMMPS plugin's ``all_laws()`` name the same laws.
A law without a compiled kernel yet (numpy and the scalar reference only) is listed in
``PYTHON_LAWS`` instead: get_law, fit and collide take it; the C kernel and the plugin do not.
"""
from __future__ import annotations

from . import hertz, thornton, vz, vz_table, vz_unload, walton_braun
from .contact_law import ContactDetails, ContactLaw

LAWS: dict[str, ContactLaw] = {law.name: law for law in (hertz.LAW, vz.LAW, vz_table.LAW, thornton.LAW,
                                                         walton_braun.LAW, vz_unload.LAW)}

PYTHON_LAWS: dict[str, ContactLaw] = {}     # every law has its compiled kernel

__all__ = ["LAWS", "PYTHON_LAWS", "ContactDetails", "ContactLaw", "get_law"]


def get_law(name: str) -> ContactLaw:
    """The force law called ``name``: one of 'hertz', 'vz', 'vz-table', 'thornton', 'walton-braun',
    'vz-unload'."""
    laws = {**LAWS, **PYTHON_LAWS}
    if not isinstance(name, str) or name.strip().lower() not in laws:
        raise ValueError(f"law must be one of {', '.join(laws)}; got {name!r}")
    return laws[name.strip().lower()]
