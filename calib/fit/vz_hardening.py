"""The hardening sheet of the vz master table: the laws of a sphere of linear isotropic hardening.

A sphere whose flow stress grows with the equivalent plastic strain eps_p as

    sigma_y(eps_p) = sigma_Y + H eps_p        (H [Pa] the plastic modulus; calib.fe.flow_curve)

yields first at the same P_Y, a_Y, delta_Y as the perfectly plastic one (H acts only once eps_p > 0). In
small strain the plastic strain at a load x = P/P_Y scales with sigma_Y / E, so at x the flow stress is
sigma_Y (1 + (H/E) eps_p E/sigma_Y): the dimensionless hardening is H/E, and the tables of the laws at x
(f = a_p/a_Y, g = C_R, the vz-unload law's rho, m and f_a; calib.fit.vz_master_table) are functions of
(nu, E/sigma_Y, H/E). The sheet holds them at nu = 0.3 over the grid's E/sigma_Y columns and H/E 0, 0.005,
0.02 and 0.05 (scene vz_master_hardening, the grid's mesh and window: 250 P_Y or the small strain's reach),
and a material's tables are the master table's plus the hardening's share measured at nu 0.3:

    T(nu, E/sigma_Y, H/E; x) = T_master(nu, E/sigma_Y; x) + [T_s(H/E, E/sigma_Y; x) - T_s(0, E/sigma_Y; x)]

T_s the sheet interpolated as the master table interpolates nu and E/sigma_Y (PCHIP in H/E, then in
log10 E/sigma_Y, over the columns reaching x; T_s(0) is the master table's own nu 0.3 nodes). Its window is
the master table's to the sheet's top at that E/sigma_Y (the small strain's reach: no finite-strain hardening
sheet). How far the share depends on nu, and the law's accuracy between the sheet's nodes, are measured on the
scene's [[check]] spheres (FE paths with hardening at other nu, E/sigma_Y and H/E): :func:`check_rows`,
results/tables/vz_master_hardening/.

    nfdcal table vz_master_hardening [--workers 2] --master-out calib/data/vz_hardening_table.csv
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from calib import output
from calib.fit.master_table import DATA_DIR, read_meta, read_rows
from calib.fit.vz_master_table import RADIUS_COLUMN, UNLOADING_COLUMNS, VZMasterTable, proportional_below
from nfdmodel import ContactPair, Material, VZTableParams, VZUnloadParams
from nfdmodel.vz_unload import HERTZ_EXPONENT

DEFAULT_SHEET = DATA_DIR / "vz_hardening_table.csv"
SCENE = "vz_master_hardening"
SHARED = ("f", "g", "rho", "m", "q")            # the tables the hardening shifts (VZMasterTable.tables' keys; q below)


def radius_ratio(x: np.ndarray, f: np.ndarray, f_a: np.ndarray) -> np.ndarray:
    """q = (x^(1/3) + f_a) / (x^(1/3) + f): the vz-unload law's contact radius over the vz-table law's [-]."""
    c = np.cbrt(x)
    return (c + f_a) / (c + f)


@dataclasses.dataclass(frozen=True)
class HardeningSheet:
    """The sheet as a VZMasterTable whose first axis is H/E (its ``nu`` column holds H/E), at ``nu``."""
    table: VZMasterTable
    nu: float
    meta: dict

    @classmethod
    def load(cls, path: str | Path | None = None) -> "HardeningSheet":
        path = Path(path) if path is not None else DEFAULT_SHEET
        rows = read_rows(path)
        meta = read_meta(path, "vz_hardening_table")
        as_master = [{**r, "nu": r["H_over_E"]} for r in rows]
        return cls(VZMasterTable.from_rows(as_master, meta, path), float(rows[0]["nu"]), meta)

    @property
    def path(self) -> Path | None:
        return self.table.path

    @property
    def accuracy(self) -> str:
        return self.meta.get("accuracy", "not stated")

    @property
    def H_over_E_range(self) -> tuple[float, float]:
        return float(self.table.nu[0]), float(self.table.nu[-1])

    def check(self, H_over_E: float) -> None:
        """ValueError naming H/E and the sheet's range when outside it."""
        low, high = self.H_over_E_range
        if not low <= H_over_E <= high * (1 + 1e-12):
            raise ValueError(f"--hardening-modulus out of range: H/E = {H_over_E:.4g}, the vz master table's hardening "
                             f"sheet spans H/E {low:g} to {high:g} (H at most {high:g} E); for a stiffer hardening run "
                             f"the FE, nfdcal calibrate --hardening-modulus H")

    def share(self, H_over_E: float, E_over_sigma_y: float) -> dict:
        """The hardening's share T_s(H/E) - T_s(0) of each table at E/sigma_Y on the sheet's loads, and the
        sheet's top there [P_Y]."""
        self.check(H_over_E)
        hardened = self.table.tables(H_over_E, E_over_sigma_y)
        plain = self.table.tables(0.0, E_over_sigma_y)
        for values in (hardened, plain):        # the vz-unload radius as its ratio to the vz-table law's
            if "f_a" in values:
                values["q"] = radius_ratio(values["x"], values["f"], values["f_a"])
        return {"x": hardened["x"], "top": hardened["top"],
                **{key: hardened[key] - plain[key] for key in SHARED if key in hardened}}


def hardened_tables(master: VZMasterTable, sheet: HardeningSheet, nu: float, E_over_sigma_y: float,
                    H_over_E: float) -> dict:
    """The tables of (nu, E/sigma_Y, H/E) (module doc) on the sheet's loads up to the lower top, as
    VZMasterTable.tables gives them (x, f, g, low, top, rho, m, f_a, rel_error_estimate): the master table's,
    interpolated in x by each law's own monotone cubic where its loads are not the sheet's, plus the share."""
    from nfdmodel.pchip import pchip_evaluate, pchip_slopes

    base = master.tables(nu, E_over_sigma_y)
    share = sheet.share(H_over_E, E_over_sigma_y)
    top = min(base["top"], share["top"])
    x = share["x"][share["x"] <= top * (1 + 1e-9)]
    at = np.clip(x, 1.0, base["x"][-1])

    def on_x(values):
        return pchip_evaluate(base["x"], values, pchip_slopes(base["x"], values), at)[0]

    if "f_a" in base:
        base = {**base, "q": radius_ratio(base["x"], base["f"], base["f_a"])}

    out = {"x": x, "top": float(x[-1]), "low": min(base["low"], float(x[-1])),
           "rel_error_estimate": base["rel_error_estimate"],
           "source_note": (f"; hardening H/E {H_over_E:.4g}: the hardening's share of the tables measured at nu "
                           f"{sheet.nu:g} ({sheet.table.path.name if sheet.table.path else 'hardening sheet'}, "
                           f"small strain)")}
    for key in SHARED:
        if key in base and key in share:
            out[key] = on_x(base[key]) + share[key][:x.size]
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
    """The master table with the hardening sheet at one H/E: ``law`` and ``unload_law`` of a material, as
    VZMasterTable's (what calib.fit.vz_master_check drives)."""
    master: VZMasterTable
    sheet: HardeningSheet
    H_over_E: float

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


def sheet_rows(rows: list[dict]) -> list[dict]:
    """The sheet's CSV rows from the scene's records: each node's columns (calib.fit.vz_master_build.node_columns)
    on the sheet's loads, its H/E beside nu and E/sigma_Y."""
    from calib.fit import vz_master_build

    nodes = sorted((r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"),
                   key=lambda r: (r.get("H_over_E", 0.0), r["nu"], r["E_over_sigma_y"]))
    loading = vz_master_build.loading_records(rows)
    x = vz_master_build.table_loads(nodes)
    out = []
    for row in nodes:
        columns = vz_master_build.node_columns(row, loading[row["key"]], x)
        window = (row["window"]["P_min_over_P_Y"], row["window"]["P_max_over_P_Y"])
        out += [{"H_over_E": row.get("H_over_E", 0.0), **r}
                for r in vz_master_build.node_rows(row, columns, x, window, row["table_rel_error_estimate"])]
    return out


def check_rows(rows: list[dict], master: VZMasterTable, sheet: HardeningSheet) -> dict:
    """The hardened laws against the scene's [[check]] FE paths (calib.fit.vz_master_check.check_material and
    check_unloading at each check's H/E) and, for contrast, the perfectly plastic master law on the same paths."""
    from calib.fit import vz_master_check

    out = {"vz-table": [], "unloading": [], "perfectly plastic": []}
    for row in (r for r in rows if r.get("kind") == "check" and r.get("status") == "ok"):
        hardened = HardenedMasterTable(master, sheet, row["H_over_E"])
        tag = {"H_over_E": row["H_over_E"]}
        out["vz-table"] += [{**tag, **r} for r in vz_master_check.check_material(row, hardened)]
        out["unloading"] += [{**tag, **r} for r in vz_master_check.check_unloading(row, hardened)]
        out["perfectly plastic"] += [{**tag, **r} for r in vz_master_check.check_material(row, master)]
    return out


def summary(checked: dict) -> dict:
    """The largest errors inside the windows: e and force of the vz-table law, the vz-unload law's e, dent
    and unloading force, and the perfectly plastic law's e and force on the same paths."""
    def largest(rows, key):
        values = [abs(r[key]) for r in rows if r["inside"] and r.get(key) is not None]
        return max(values) if values else None

    inside = [r for r in checked["vz-table"] if r["inside"]]
    return {"paths": len(inside), "checks": len({r["name"] for r in inside}),
            "vz-table": {"e_error": largest(checked["vz-table"], "e_error"),
                         "force_error": largest(checked["vz-table"], "force_error")},
            "vz-unload": {"e_error": largest(checked["unloading"], "vz-unload e_error"),
                          "unloading_error": largest(checked["unloading"], "vz-unload unloading_error"),
                          "dent_error_of_alpha_max": largest(checked["unloading"], "vz-unload dent_error_of_alpha_max")},
            "perfectly plastic": {"e_error": largest(checked["perfectly plastic"], "e_error"),
                                  "force_error": largest(checked["perfectly plastic"], "force_error")}}


def statement(measured: dict) -> str:
    """The sheet's accuracy in one sentence (:func:`summary`)."""
    if not measured["paths"]:
        return "not checked against FE paths with hardening"
    t, u, p = measured["vz-table"], measured["vz-unload"], measured["perfectly plastic"]
    return (f"against direct FE of {measured['checks']} hardening spheres off the sheet's nodes ({measured['paths']} "
            f"load-unload paths inside the window, nu {measured['nu_range']}, H/E {measured['H_over_E_range']}): "
            f"vz-table e within {100 * t['e_error']:.2g} %, force within {100 * t['force_error']:.2g} % of P_max; "
            f"vz-unload e within {100 * u['e_error']:.2g} %, unloading force {100 * u['unloading_error']:.2g} % of "
            f"P_max, dent {100 * u['dent_error_of_alpha_max']:.2g} % of alpha_max; the perfectly plastic master law "
            f"on the same paths: e {100 * p['e_error']:.2g} %, force {100 * p['force_error']:.2g} %")


def build(rows: list[dict], path: str | Path, folder: str | Path, master: VZMasterTable | None = None) -> dict:
    """Write the sheet (calib/data/vz_hardening_table.{csv,json}: its rows, stamp and measured accuracy) from the
    scene's records ``rows``, check it with the master table (default: the shipped one) against the scene's
    [[check]] FE paths (``folder``/vz_hardening_check.{csv,json}) and return the summary with its statement."""
    from calib.fit import vz_master_build

    path, folder = Path(path), Path(folder)
    scene = vz_master_build.load_scene(SCENE)
    nodes = [r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"]
    expected = len(scene["nu"]) * len(scene["E_over_sigma_y"]) * len(scene["H_over_E"])
    if len(nodes) != expected:
        raise ValueError(f"hardening sheet: {len(nodes)} of {expected} nodes are calibrated; run "
                         f"nfdcal table {SCENE} to the end first")
    table = sheet_rows(rows)
    loading = [r for r in rows if r.get("kind") == "loading" and r.get("status") == "ok"]
    stamp = output.stamp(sum(r["wall_time_s"] for r in nodes + loading),
                         mesh={"graded": vz_master_build.grid_mesh(scene), "meshes": scene["meshes"]},
                         scene=SCENE, node_commits=sorted({r["git_commit"] for r in nodes}))
    meta = {"scene": SCENE, "axes": ["H_over_E", "E_over_sigma_y", "P_over_P_Y"], "nu": scene["nu"],
            "H_over_E": scene["H_over_E"], "E_over_sigma_y": scene["E_over_sigma_y"],
            "definition": "the columns of calib/data/vz_master_table.csv of a sphere of linear isotropic hardening "
                          "sigma_y = sigma_Y + H eps_p, H = H_over_E E, at nu (calib.fit.vz_hardening)",
            "columns": ["a_p_over_a_Y", "C_R", *UNLOADING_COLUMNS, RADIUS_COLUMN]}
    output.write_csv(path, table, comment=output.stamp_comment(stamp))
    output.write_json(path.with_suffix(".json"), {"vz_hardening_table": meta, "stamp": stamp})
    master = master or VZMasterTable.load()
    checked = check_rows(rows, master, HardeningSheet.load(path))
    measured = summary(checked)
    inside = [r for r in checked["vz-table"] if r["inside"]]
    measured["nu_range"] = f"{min(r['nu'] for r in inside):g}-{max(r['nu'] for r in inside):g}" if inside else ""
    measured["H_over_E_range"] = (f"{min(r['H_over_E'] for r in inside):g}-{max(r['H_over_E'] for r in inside):g}"
                                  if inside else "")
    measured["statement"] = statement(measured)
    check_stamp = output.stamp(0.0, table=str(path), master_table=str(master.path))
    output.write_csv(folder / "vz_hardening_check.csv", checked["vz-table"], comment=output.stamp_comment(check_stamp))
    output.write_json(folder / "vz_hardening_check.json", {**checked, "accuracy": measured, "stamp": check_stamp})
    output.write_json(path.with_suffix(".json"), {"vz_hardening_table": {**meta, "accuracy": measured["statement"],
                                                                         "accuracy_details": measured},
                                                  "stamp": stamp})
    return measured
