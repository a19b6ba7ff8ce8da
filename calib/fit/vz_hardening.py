"""The hardening sheet of the vz master table: the laws of a sphere of linear isotropic hardening.

A sphere whose flow stress grows with the equivalent plastic strain eps_p as

    sigma_y(eps_p) = sigma_Y + H eps_p        (H [Pa] the plastic modulus; calib.fe.flow_curve)

yields first at the same P_Y, a_Y, delta_Y as the perfectly plastic one (H acts only once eps_p > 0). In
small strain the plastic strain at a load x = P/P_Y scales with sigma_Y / E, so at x the flow stress is
sigma_Y (1 + (H/E) eps_p E/sigma_Y): the dimensionless hardening is H/E, and the tables of the laws at x
(f = a_p/a_Y, g = C_R, the vz-unload law's rho, m and f_a; calib.fit.vz_master_table) are functions of
(nu, E/sigma_Y, H/E). The sheet holds them at nu 0.2, 0.3 and 0.49 (the master table's ends and middle) over the
grid's E/sigma_Y columns and H/E 0, 0.005, 0.02 and 0.05, and a material's tables are the master table's plus the
hardening's share:

    f, g:       T(nu, E/sigma_Y, H/E; x) = T_master(nu, E/sigma_Y; x) S(nu, E/sigma_Y, H/E; x)
    rho, m, q:  T(nu, E/sigma_Y, H/E; x) = T_master(nu, E/sigma_Y; x) + D(nu, E/sigma_Y, H/E; x)

    S = T_s(nu_i, H/E) / T_s(nu_i, 0),  D = T_s(nu_i, H/E) - T_s(nu_i, 0)  at each sheet nu_i, then PCHIP in nu

(q the vz-unload radius over the vz-table law's, :func:`radius_ratio`). T_s(nu_i) is the sheet at nu_i
interpolated as the master table interpolates nu and E/sigma_Y (PCHIP in H/E, then in log10 E/sigma_Y, over the
E/sigma_Y columns reaching the window's top; T_s(nu_i, 0) is the master table's own nodes); the share's top is
the lowest of the nus' tops. The shipped sheet is joined as the master table is (calib.fit.vz_master_join): the
small-strain scene vz_master_hardening (the grid's mesh, to 250 P_Y or the small strain's reach) below each
node's join load, a = 0.05 R, and the finite-strain scene vz_master_reach_hardening (vz_master_reach's mesh, to
1e4 P_Y or 0.45 R) from it on; the join load is the perfectly plastic node's at every H/E, so the share compares
like with like. A material's window is the master table's to the sheet's top at that E/sigma_Y. The law's
accuracy between the sheet's nodes (nu, E/sigma_Y and H/E) is measured on the scenes' [[check]] spheres (FE
paths of hardening spheres off the nodes): calib.fit.vz_hardening_build, results/tables/vz_master_reach_hardening/
(and vz_master_hardening/ for the small-strain sheet alone).
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from calib.fit.master_table import DATA_DIR, read_meta, read_rows
from calib.fit.vz_master_table import VZMasterTable, pchip_along, proportional_below
from nfdmodel import ContactPair, Material, VZTableParams, VZUnloadParams
from nfdmodel.vz_unload import HERTZ_EXPONENT

DEFAULT_SHEET = DATA_DIR / "vz_hardening_table.csv"
SCENE = "vz_master_hardening"
# How each table (VZMasterTable.tables' keys; q below) takes the hardening's share: as a factor, T_s(H/E) / T_s(0),
# or as a difference, T_s(H/E) - T_s(0). The plastic radius f and C_R g as factors: hardening shrinks them by a
# fraction that depends less on nu than their difference does (nu 0.2, E/sigma_Y 300, H/E 0.02, 3539 P_Y,
# finite strain: e 0.85 % from the FE as factors, 2.4 % as differences)
# Tabor's constant c_T of the representative strain c_T a/R at which a flow curve's secant modulus is read
# (:func:`representative_strain`)
REPRESENTATIVE_STRAIN_FACTOR = 0.2
SHARED = {"f": "factor", "g": "factor", "rho": "difference", "m": "difference", "q": "difference"}
# Below this plain plastic radius f = a_p/a_Y (just above P_Y the FE's f is 1e-5-1e-2) a factor is noise, so it is
# 1 there: at E/sigma_Y 100, H/E 0.2, 1.33 P_Y the raw factor is 183 at nu 0.2 and 245 at nu 0.49 (f 1.1e-5), and
# PCHIP in nu put 56 at nu 0.25, f 0.31 instead of about 0.005
FACTOR_FLOOR = 0.02


def radius_ratio(x: np.ndarray, f: np.ndarray, f_a: np.ndarray) -> np.ndarray:
    """q = (x^(1/3) + f_a) / (x^(1/3) + f): the vz-unload law's contact radius over the vz-table law's [-]."""
    c = np.cbrt(x)
    return (c + f_a) / (c + f)


@dataclasses.dataclass(frozen=True)
class HardeningSheet:
    """The sheet: at each of its Poisson's ratios ``nus`` a VZMasterTable whose first axis is H/E (its ``nu``
    column holds H/E); the share at another nu is the PCHIP in nu of the shares at ``nus`` (module doc)."""
    tables_at_nu: tuple[VZMasterTable, ...]
    nus: tuple[float, ...]
    meta: dict
    path: Path | None = None

    @classmethod
    def load(cls, path: str | Path | None = None) -> "HardeningSheet":
        path = Path(path) if path is not None else DEFAULT_SHEET
        rows = read_rows(path)
        meta = read_meta(path, "vz_hardening_table")
        nus = sorted({float(r["nu"]) for r in rows})
        tables = tuple(VZMasterTable.from_rows([{**r, "nu": r["H_over_E"]} for r in rows if float(r["nu"]) == nu],
                                               meta, path) for nu in nus)
        if any(not np.array_equal(t.x, tables[0].x) for t in tables):
            raise ValueError(f"hardening sheet {path}: its nus' loads P_over_P_Y differ; rebuild it with nfdcal table")
        return cls(tables, tuple(nus), meta, path)

    @property
    def accuracy(self) -> str:
        return self.meta.get("accuracy", "not stated")

    @property
    def flow_curve_accuracy(self) -> str:
        """The sheet's accuracy for a flow curve read through its secant modulus (hardened_tables)."""
        return self.meta.get("accuracy_flow_curves", "not stated")

    @property
    def kinematics(self) -> str:
        """How the sheet's FE ran: small strain, or joined to finite strain (calib.fit.vz_master_join)."""
        join = self.meta.get("join")
        if join:
            return f"small strain below a = {join['join_a_over_R']:g} R, finite strain from it"
        return "small strain"

    @property
    def nu_label(self) -> str:
        """Where the share is measured: "nu 0.3" or "nu 0.2, 0.3, 0.49 (PCHIP in nu between)"."""
        if len(self.nus) == 1:
            return f"nu {self.nus[0]:g}"
        return f"nu {', '.join(f'{nu:g}' for nu in self.nus)} (PCHIP in nu between)"

    @property
    def H_over_E_range(self) -> tuple[float, float]:
        return (max(float(t.nu[0]) for t in self.tables_at_nu), min(float(t.nu[-1]) for t in self.tables_at_nu))

    def check(self, H_over_E: float) -> None:
        """ValueError naming H/E and the sheet's range when outside it."""
        low, high = self.H_over_E_range
        if not low <= H_over_E <= high * (1 + 1e-12):
            raise ValueError(f"--hardening-modulus out of range: H/E = {H_over_E:.4g}, the vz master table's hardening "
                             f"sheet spans H/E {low:g} to {high:g} (H at most {high:g} E); for a stiffer hardening run "
                             f"the FE, nfdcal calibrate --hardening-modulus H")

    def share(self, H_over_E: float, E_over_sigma_y: float, nu: float) -> dict:
        """The hardening's share of each table at (nu, E/sigma_Y) on the sheet's loads (T_s(H/E) / T_s(0) or
        T_s(H/E) - T_s(0), SHARED), and the sheet's top there [P_Y]: at each of the sheet's nus, then PCHIP in
        nu (clamped to the sheet's nus) up to the lowest of their tops."""
        self.check(H_over_E)
        low = max(float(t.E_over_sigma_y[0]) for t in self.tables_at_nu)
        high = min(float(t.E_over_sigma_y[-1]) for t in self.tables_at_nu)
        if not low * (1 - 1e-12) <= E_over_sigma_y <= high * (1 + 1e-12):     # the master table reaches further
            raise ValueError(f"E/sigma_Y = {E_over_sigma_y:g} is outside the vz master table's hardening sheet: need "
                             f"E/sigma_Y in [{low:g}, {high:g}] for a hardening sphere (calibrate this material by FE "
                             f"with `nfdcal calibrate --v-max` and its hardening instead)")
        at_nu = [_share_at(table, H_over_E, E_over_sigma_y) for table in self.tables_at_nu]
        if len(at_nu) == 1:
            return at_nu[0]
        n = min(s["x"].size for s in at_nu)
        nus = np.array(self.nus)
        where = float(np.clip(nu, nus[0], nus[-1]))
        out = {"x": at_nu[0]["x"][:n], "top": float(at_nu[0]["x"][n - 1])}
        for key in set.intersection(*(set(s) for s in at_nu)) - {"x", "top"}:
            out[key] = pchip_along(nus, np.stack([s[key][:n] for s in at_nu]), where)
        return out


def _share_at(table: VZMasterTable, H_over_E: float, E_over_sigma_y: float) -> dict:
    """HardeningSheet.share on one nu's table (its first axis H/E)."""
    # over the same E/sigma_Y columns at every load: a column ending inside the window steps the share (by
    # 0.039 in g at E/sigma_Y 700, H/E 0.01, where E/sigma_Y 300 ends at 7350 P_Y), and g then falls
    hardened = table.tables(H_over_E, E_over_sigma_y, same_columns=True)
    plain = table.tables(0.0, E_over_sigma_y, same_columns=True)
    for values in (hardened, plain):        # the vz-unload radius as its ratio to the vz-table law's
        if "f_a" in values:
            values["q"] = radius_ratio(values["x"], values["f"], values["f_a"])
    out = {"x": hardened["x"], "top": hardened["top"]}
    for key, kind in SHARED.items():
        if key in hardened:
            out[key] = (_factor(hardened[key], plain[key], plain["f"]) if kind == "factor"
                        else hardened[key] - plain[key])
    return out


def _factor(hardened: np.ndarray, plain: np.ndarray, plastic_radius: np.ndarray) -> np.ndarray:
    """T_s(H/E) / T_s(0) along the loads; 1 where the plain plastic radius f is below FACTOR_FLOOR (the plastic
    strain, hence the hardening, vanishing towards P_Y), for f and g alike so they stay one cycle's pair."""
    sound = plastic_radius >= FACTOR_FLOOR
    return np.where(sound, hardened / np.where(sound, plain, 1.0), 1.0)


def yield_radius_over_R(nu: float, E_over_sigma_y: float) -> float:
    """a_Y / R of a sphere on a rigid flat [-] (nfdmodel.materials: it depends on nu and E/sigma_Y alone)."""
    return float(ContactPair.sphere_flat(Material(E_over_sigma_y * 1e8, nu, 1e8, 1000.0), 1.0).a_Y)


def representative_strain(x: np.ndarray, f: np.ndarray, a_Y_over_R: float) -> np.ndarray:
    """Tabor's representative plastic strain of a sphere's contact at the load x = P/P_Y [-]:

        eps_r = c_T a / R,   a / a_Y = x^(1/3) + f(x)   (the vz-table law's contact radius, f = a_p / a_Y)

    c_T = REPRESENTATIVE_STRAIN_FACTOR (Tabor 1951, The Hardness of Metals: 0.2 for a ball's indentation)."""
    return REPRESENTATIVE_STRAIN_FACTOR * a_Y_over_R * (np.cbrt(x) + f)


def effective_hardening(curve, E: float, eps_r: np.ndarray) -> np.ndarray:
    """H_eff / E [-]: the secant modulus of the flow curve ``curve`` (calib.fe.flow_curve) over [0, eps_r],

        H_eff = (sigma_y(eps_r) - sigma_Y) / eps_r,

    the linear hardening that reaches the curve's flow stress at the representative strain eps_r
    (:func:`representative_strain`); a linear curve's H at every eps_r."""
    eps_r = np.asarray(eps_r, dtype=float)
    return (np.asarray(curve.yield_stress(eps_r), dtype=float) - curve.sigma_y) / eps_r / E


def _share_along(sheet: HardeningSheet, H_over_E: np.ndarray, E_over_sigma_y: float, nu: float) -> dict:
    """HardeningSheet.share with a hardening that varies with the load (H_over_E on the sheet's loads): the
    shares at the sheet's H/E nodes, then at each load the PCHIP in H/E at that load's H/E."""
    from nfdmodel.pchip import pchip_evaluate, pchip_slopes

    nodes = np.array(sorted({float(h) for t in sheet.tables_at_nu for h in t.nu}))
    shares = [sheet.share(float(h), E_over_sigma_y, nu) for h in nodes]
    n = min(s["x"].size for s in shares)
    out = {"x": shares[0]["x"][:n], "top": float(shares[0]["x"][n - 1])}
    at = np.asarray(H_over_E, dtype=float)[:n]
    columns = np.arange(at.size)
    for key in set.intersection(*(set(s) for s in shares)) - {"x", "top"}:
        values = np.stack([s[key][:n] for s in shares])             # (H/E nodes, loads)
        evaluated = pchip_evaluate(nodes, values, pchip_slopes(nodes, values), at)[0]   # (loads at, loads)
        out[key] = evaluated[columns, columns]
    return out


def hardened_tables(master: VZMasterTable, sheet: HardeningSheet, nu: float, E_over_sigma_y: float,
                    hardening) -> dict:
    """The tables of (nu, E/sigma_Y, H/E) (module doc) on the sheet's loads up to the lower top, as
    VZMasterTable.tables gives them (x, f, g, low, top, rho, m, f_a, rel_error_estimate): the master table's,
    interpolated in x by each law's own monotone cubic where its loads are not the sheet's, plus the share.
    ``hardening``: H/E of linear hardening, or a flow curve (calib.fe.flow_curve, sigma_Y = E / E_over_sigma_y
    in its units) read as the linear hardening of its secant modulus at each load's representative strain
    (:func:`effective_hardening`)."""
    from nfdmodel.pchip import pchip_evaluate, pchip_slopes

    base = master.tables(nu, E_over_sigma_y)

    def on(loads, values):
        at = np.clip(loads, 1.0, base["x"][-1])
        return pchip_evaluate(base["x"], values, pchip_slopes(base["x"], values), at)[0]

    if np.ndim(hardening) == 0 and not hasattr(hardening, "yield_stress"):
        H_over_E = float(hardening)
        share = sheet.share(H_over_E, E_over_sigma_y, nu)
        named = f"H/E {H_over_E:.4g}"
    else:
        loads = sheet.tables_at_nu[0].x
        E = hardening.sigma_y * E_over_sigma_y
        H_over_E = effective_hardening(hardening, E, representative_strain(
            loads, on(loads, base["f"]), yield_radius_over_R(nu, E_over_sigma_y)))
        low, high = sheet.H_over_E_range
        inside = np.nonzero(loads <= base["top"] * (1 + 1e-9))[0]
        worst = inside[np.argmax(H_over_E[inside])]
        if H_over_E[worst] > high * (1 + 1e-12):
            raise ValueError(f"--flow-curve out of range: its secant modulus at the contact's representative strain "
                             f"(eps_r {REPRESENTATIVE_STRAIN_FACTOR:g} a/R) reaches {H_over_E[worst]:.4g} E at "
                             f"{loads[worst]:.3g} P_Y, beyond the hardening sheet's H/E {high:g}; run the FE of this "
                             f"sphere instead, nfdcal calibrate --flow-curve CSV")
        share = _share_along(sheet, H_over_E, E_over_sigma_y, nu)
        read_as = (f"read as linear hardening of H/E {H_over_E[inside].min():.3g}-{H_over_E[inside].max():.3g} "
                   f"(its secant modulus to the representative strain {REPRESENTATIVE_STRAIN_FACTOR:g} a/R)")
        named = f"flow curve {read_as}"
    top = min(base["top"], share["top"])
    x = share["x"][share["x"] <= top * (1 + 1e-9)]

    def on_x(values):
        return on(x, values)

    if "f_a" in base:
        base = {**base, "q": radius_ratio(base["x"], base["f"], base["f_a"])}

    out = {"x": x, "top": float(x[-1]), "low": min(base["low"], float(x[-1])),
           "rel_error_estimate": base["rel_error_estimate"],
           **({} if np.ndim(H_over_E) == 0 else {"hardening_read_as": read_as}),
           "source_note": (f"; hardening {named}: the hardening's share of the tables measured at "
                           f"{sheet.nu_label} ({sheet.path.name if sheet.path else 'hardening sheet'}, "
                           f"{sheet.kinematics})")}
    for key, kind in SHARED.items():
        if key in base and key in share:
            out[key] = on_x(base[key]) * share[key][:x.size] if kind == "factor" else on_x(base[key]) + share[key][:x.size]
    out["f"] = np.maximum.accumulate(np.maximum(out["f"], 0.0))     # a plastic radius: >= 0, growing
    out["f"][0], out["g"][0] = 0.0, 1.0
    out["g"] = proportional_below(x, out["f"], out["g"], out["low"])
    if "q" in out:                      # the radius from its ratio: its hardening share kept with f's
        c = np.cbrt(x)
        # g_a = g q^2 (VZMasterTable.vz_unload_of) kept non-decreasing: a g_a falling at the top (E/sigma_Y > 1000,
        # H/E >= 0.02), continued straight, bends the vz-unload law's loading curve back (delta(P) not increasing)
        # before full contact: 19 of 504 laws refused (7 nu x 12 E/sigma_Y x 6 H/E); kept, none, the radius moved
        # by at most 0.38 %
        g_a = np.maximum.accumulate(out["g"] * out.pop("q") ** 2)
        f_a = np.sqrt(g_a / out["g"]) * (c + out["f"]) - c
        out["f_a"] = np.maximum.accumulate(np.maximum(f_a, 0.0))
        out["f_a"][0] = 0.0
    if "rho" in out:
        out["rho"][0], out["m"][0] = 0.0, HERTZ_EXPONENT
    return out


@dataclasses.dataclass(frozen=True)
class HardenedMasterTable:
    """The master table with the hardening sheet at one H/E (or a flow curve: hardened_tables): ``law`` and
    ``unload_law`` of a material, as VZMasterTable's (what calib.fit.vz_master_check drives)."""
    master: VZMasterTable
    sheet: HardeningSheet
    H_over_E: object

    def _values(self, material: Material) -> dict:
        return hardened_tables(self.master, self.sheet, float(material.nu), float(material.E / material.sigma_y),
                               self.H_over_E)

    def law(self, material: Material, R: float) -> VZTableParams:
        return self.master.vz_table_of(self._values(material), ContactPair.sphere_flat(material, R))

    def unload_law(self, material: Material, R: float) -> VZUnloadParams:
        return self.master.vz_unload_of(self._values(material), ContactPair.sphere_flat(material, R))

    def __getattr__(self, name):
        # the master table's axes, metadata and accuracy (what a fit reads besides the laws)
        if name == "master":
            raise AttributeError(name)
        return getattr(self.master, name)
