"""Benchmark: the rate-aware law's c checked off the reference sphere, against the dynamic FE with the rate law.

Not a timed test. For six spheres on the rigid flat (the reference aluminium E 70 GPa, nu 0.3, sigma_Y 100 MPa,
R 0.1 m; E/sigma_Y 300 and 1500; nu 0.25 and 0.4; R 0.05 m; rho 2699 kg/m^3) at v_in = 6, 12, 24 v_Y (each
sphere's own yield velocity: the reference's 0.01, 0.02, 0.04 m/s), ``nfdcal impact`` on the coarse mesh (contact
element 1.6e-4 m a_Y / a_Y,ref: the same mesh relative to the contact; 100 steps per contact, no error estimate)
rate-independent, with Cowper-Symonds D 40 /s q 5 (mild) and D 2 /s q 1 (strong), against the rate-aware law on
the vz master table's vz-table law of that sphere (calib.fit.measured.rate_fit.rate_params, c = 26). Prints per
case: the law's R, the FE's e, the law's e error, the rate-independent law's error against the rate-independent
FE (the base law's own error), and two c: c_e, the c whose rate-aware e equals the FE's, and c_rate, the c
whose ratio e_rate / e_rate-independent equals the FE's (the base law's own error removed); each by a 1-D root
find on the law's exact energy balance. The same for the self-consistent variant (``SELF``): a_ref the rate-aware
law's own contact radius at its peak (R a_0 at v_n0 / R^(5/2)), eps_dot = v_n0 / (c a_ref(R)) solved for R,
its c fitted on the reference's mild law at 0.02 m/s alone (as c = 26 was) and checked on every other case; the
PLASTIC variant (the FE's R is a function of the equivalent plastic strain rate: eps_dot = v_n0 (1 - e_0^2)^(1/2) /
(c a_ref), e_0 the base law's e at v_n0 / R^(5/2), solved for R), its c fitted on the reference's strong law at
0.02 m/s; and PLASTIC-Q (PLASTIC with R averaged over a log-normal spread of strain rates, log-variance s^2:
Cowper-Symonds' c_q = c0 exp(-s^2 / (2 q)), Johnson-Cook's clipped ln averaged in closed form), c0 and s^2
fitted on the reference at 0.02 m/s with both laws, checked on the other cases and on the stored drop tests of
tests/data/rate_fe_drops.json.
``--fine``: one finer mesh (the reference, strong law, the three speeds, contact element 1.1e-4 m). ``--dem``: a DEM
user's sphere at DEM strain rates (mild steel, R 2 mm, 0.03-0.3 m/s: 44-135 /s, R to 2.3; dem_rates), with mild
steel's Cowper-Symonds law and a Johnson-Cook law, on the impact's default mesh. The FE records are kept in ``--out``
(rerunning reuses them). About 4 minutes on one core (1 minute with the records; 8 minutes with ``--dem``).
Usage: .venv/bin/python tests/benchmarks/bench_rate_materials.py [--out DIR] [--fine] [--dem]
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import tempfile
import warnings
from pathlib import Path

import numpy as np
from scipy.optimize import brentq
from scipy.stats import norm

from calib.cli import main
from calib.fit.measured import rate_fit
from calib.fit.measured.rate_fit import predict, rate_params
from calib.fit.measured.specimen import Specimen
from calib.fit.measured.table_law import table_law
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import RangeWarning, collision_reference
from nfdmodel.materials import ContactPair
from nfdmodel.rate_aware import BASE_LAWS_LAW, RATE_LENGTH_FACTOR
from nfdmodel.strain_rate import CowperSymonds, JohnsonCook, rate_law_of

DATA = Path(__file__).resolve().parents[1] / "data" / "rate_fe_drops.json"
RHO = 2699.0
MATERIALS = {"reference": (70e9, 0.3, 100e6, 0.1), "E/sigma_Y 300": (70e9, 0.3, 70e9 / 300, 0.1),
             "E/sigma_Y 1500": (70e9, 0.3, 70e9 / 1500, 0.1), "nu 0.25": (70e9, 0.25, 100e6, 0.1),
             "nu 0.4": (70e9, 0.4, 100e6, 0.1), "R 0.05 m": (70e9, 0.3, 100e6, 0.05)}
MULTIPLES = (6.0, 12.0, 24.0)              # v_in / v_Y (the reference's 0.01, 0.02, 0.04 m/s)
RATE_LAWS = {"independent": None, "CS D40 q5": (40.0, 5.0), "CS D2 q1": (2.0, 1.0)}
CONTACT_SIZE = 1.6e-4                      # the coarse mesh's contact element at the reference's a_Y [m]
FINE_SIZE = 1.1e-4
C_BRACKET = (0.05, 1e5)
DEM_NAME = "mild steel E 210 GPa, nu 0.3, sigma_Y 250 MPa, rho 7850 kg/m^3, R 2 mm"
DEM_SPHERE = (210e9, 0.3, 250e6, 0.002)
DEM_RHO = 7850.0
DEM_SPEEDS = (0.03, 0.1, 0.3)              # 28, 93, 278 v_Y
# mild steel's Cowper-Symonds law (Jones 2012) and a Johnson-Cook law of its strength (Armco iron's C, Johnson & Cook
# 1985): (kind, the rate constant, D's q or Johnson-Cook's eps_dot_0)
DEM_RATE_LAWS = {"CS D40.4 q5": ("cowper-symonds", 40.4, 5.0), "JC C0.06": ("johnson-cook", 0.06, 1.0)}
FITTED_ON = {"SELF": "CS D40 q5", "PLASTIC": "CS D2 q1"}   # each variant's c: fitted on the reference at 12 v_Y


def pair_of(material) -> ContactPair:
    E, nu, sigma_y, R = material
    return ContactPair.sphere_flat(Specimen(E, nu, R, RHO).material(sigma_y), R)


def fe_restitution(material, rate, speeds, size, folder: Path, rho: float = RHO) -> list:
    """The FE's e at ``speeds``: ``rate`` None, (D, q) of Cowper-Symonds or the flags of a rate law; ``size``
    the contact element [m] or None (the impact's default mesh)."""
    E, nu, sigma_y, R = material
    if rate is None or isinstance(rate[0], str):
        flags = list(rate or ())
    else:
        flags = ["--rate-law", "cowper-symonds", "--cs-D", repr(rate[0]), "--cs-q", repr(rate[1])]
    mesh = [] if size is None else ["--contact-size", f"{size:.4g}"]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["impact", "--E", repr(E), "--nu", repr(nu), "--sigma-y", repr(sigma_y), "--R", repr(R),
                     "--rho", repr(rho), "--v-in", *map(repr, speeds), *mesh, *flags, "--no-error-estimate",
                     "--no-quasi-static", "--no-plots", "--workers", "1", "--out", str(folder), "--json", "--quiet"])
    assert code == 0
    return [record["e"] for record in json.loads(printed.getvalue())]


def fe_records(out: Path, fine: bool) -> dict:
    """{material: {rate law: [e per speed]}} of the FE, read from out/fe.json where present."""
    store = out / "fe.json"
    records = json.loads(store.read_text()) if store.exists() else {}
    jobs = [(name, law, MATERIALS[name], CONTACT_SIZE) for name in MATERIALS for law in RATE_LAWS]
    if fine:
        jobs.append(("reference fine", "CS D2 q1", MATERIALS["reference"], FINE_SIZE))
    for name, law, material, size in jobs:
        if law in records.get(name, {}):
            continue
        pair = pair_of(material)
        speeds = [m * pair.v_Y for m in MULTIPLES]
        scale = pair.a_Y / pair_of(MATERIALS["reference"]).a_Y
        records.setdefault(name, {})[law] = fe_restitution(material, RATE_LAWS[law], speeds, size * scale,
                                                           out / f"{name}-{law}".replace(" ", "_").replace("/", ""))
        store.write_text(json.dumps(records, indent=1))
    return records


def law_e(material, table, rate, v, c):
    """The rate-aware law's e at v [m/s] with c (c_e's root find)."""
    E, nu, sigma_y, R = material
    params = rate_params(Specimen(E, nu, R, RHO), table, "cowper-symonds", sigma_y, rate[0], rate[1], c)
    base = collision_reference(BASE_LAWS_LAW["vz-table"], params.base, [v / params.rate_factor([v])[0] ** 2.5])
    return float(base.restitution[0])


def variant_factor(base, rate_law, v, c, variant):
    """R solving R = R(v w(R) / (c a(R))) of a variant of the law: SELF, a(R) = R a_0(peak of the base law at
    v / R^(5/2)), w = 1; PLASTIC, a = a_ref (the law's), w(R) = (1 - e_0^2)^(1/2), e_0 the base law's e at
    v / R^(5/2) (the share of the impact's energy the contact dissipates: the FE's rate is a plastic strain rate)."""
    a_ref = float(base.contact_radius_at(collision_reference(BASE_LAWS_LAW["vz-table"], base, [v]).P_max)[0])

    def rate(factor):
        ref = collision_reference(BASE_LAWS_LAW["vz-table"], base, [v / factor**2.5])
        if variant == "SELF":
            return v / (c * factor * float(base.contact_radius_at(ref.P_max)[0]))
        return v * np.sqrt(max(1.0 - float(ref.restitution[0]) ** 2, 0.0)) / (c * a_ref)

    def gap(factor):
        return factor - float(rate_law.factor(np.array([rate(factor)]))[0])
    high = 2.0
    while gap(high) < 0.0:
        high *= 2.0
    return brentq(gap, 1.0, high, xtol=1e-12) if gap(1.0) < 0.0 else 1.0


def variant_e(material, table, rate, v, c, variant):
    E, nu, sigma_y, R = material
    base = table_law(Specimen(E, nu, R, RHO), sigma_y, table)
    factor = variant_factor(base, CowperSymonds(*rate), v, c, variant)
    return float(collision_reference(BASE_LAWS_LAW["vz-table"], base, [v / factor**2.5]).restitution[0])


class JohnsonCookSpread:
    """Johnson-Cook's R averaged over a log-normal spread of strain rates (log standard deviation ``s``) about
    the median rate it is given (plastic_q_e)."""

    def __init__(self, law: JohnsonCook, s: float):
        self.law, self.s = law, s

    def factor(self, rate):
        m = np.log(np.maximum(rate, 1e-300) / self.law.reference_rate)
        return 1.0 + self.law.C * (m * norm.cdf(m / self.s) + self.s * norm.pdf(m / self.s))


def plastic_q_e(material, table, rate_law, v, c0, s2, rho=RHO):
    """PLASTIC with R averaged over log-normally spread plastic strain rates of log-variance s^2 about the median
    v_n0 (1 - e_0^2)^(1/2) / (c0 a_ref): Cowper-Symonds E[(eps_dot / D)^(1/q)] = (median / D)^(1/q)
    exp(s^2 / (2 q^2)), i.e. c_q = c0 exp(-s^2 / (2 q)); Johnson-Cook E[max(ln(eps_dot / eps_dot_0), 0)] =
    m Phi(m / s) + s phi(m / s), m = ln(median / eps_dot_0) (JohnsonCookSpread)."""
    E, nu, sigma_y, R = material
    base = table_law(Specimen(E, nu, R, rho), sigma_y, table)
    if isinstance(rate_law, CowperSymonds):
        factor = variant_factor(base, rate_law, v, c0 * np.exp(-s2 / (2.0 * rate_law.q)), "PLASTIC")
    else:
        factor = variant_factor(base, JohnsonCookSpread(rate_law, np.sqrt(s2)), v, c0, "PLASTIC")
    return float(collision_reference(BASE_LAWS_LAW["vz-table"], base, [v / factor**2.5]).restitution[0])


def plastic_q(records, table) -> tuple:
    """PLASTIC-Q: c0, s^2 from PLASTIC's c fitted on the reference at 12 v_Y with q 1 and q 5; checked on every
    other case and on the stored drop tests of tests/data/rate_fe_drops.json (Johnson-Cook among them)."""
    ref = MATERIALS["reference"]
    v_ref = 12.0 * pair_of(ref).v_Y
    c = {q: root_c(lambda c: variant_e(ref, table, RATE_LAWS[law], v_ref, c, "PLASTIC"), records["reference"][law][1])
         for q, law in ((1.0, "CS D2 q1"), (5.0, "CS D40 q5"))}
    s2 = np.log(c[5.0] / c[1.0]) / (0.5 - 0.1)
    c0 = c[1.0] * np.exp(s2 / 2.0)
    print(f"\nPLASTIC-Q: c0 {c0:.4g}, s^2 {s2:.3g} (c_q1 {c[1.0]:.4g}, c_q5 {c[5.0]:.4g}); e error % at 6/12/24 v_Y:")
    for name, laws in records.items():
        material = MATERIALS["reference" if name == "reference fine" else name]
        v_y = pair_of(material).v_Y
        for law, fe in laws.items():
            if RATE_LAWS[law] is not None:
                errors = [100 * (plastic_q_e(material, table, CowperSymonds(*RATE_LAWS[law]), m * v_y, c0, s2) / f - 1)
                          for m, f in zip(MULTIPLES, fe)]
                print(f"  {name}, {law}: " + " / ".join(f"{x:+.2f}" for x in errors))
    data = json.loads(DATA.read_text(encoding="utf-8"))
    for series, entry in data["series"].items():
        rate_law = rate_law_of(entry["rate_law"])
        errors = [100 * (plastic_q_e(ref, table, rate_law, t["v_in"], c0, s2) / t["e"] - 1) for t in entry["tests"]]
        print(f"  {series} ({DATA.name}, {entry['tests'][0]['v_in']:g}..{entry['tests'][-1]['v_in']:g} m/s): "
              + " / ".join(f"{x:+.2f}" for x in errors))
    return c0, s2


def dem_records(out: Path) -> dict:
    """{rate law of DEM_RATE_LAWS or "independent": [the FE's e per DEM_SPEEDS]} of the DEM sphere on the impact's
    default mesh, read from out/fe_dem.json where present."""
    store = out / "fe_dem.json"
    records = json.loads(store.read_text()) if store.exists() else {}
    for name, (kind, constant, fixed) in {"independent": (None, None, None), **DEM_RATE_LAWS}.items():
        if name not in records:
            names = ("--cs-D", "--cs-q") if kind == "cowper-symonds" else ("--jc-C", "--jc-reference-rate")
            flags = None if kind is None else ("--rate-law", kind, names[0], repr(constant), names[1], repr(fixed))
            records[name] = fe_restitution(DEM_SPHERE, flags, DEM_SPEEDS, None, out / f"dem-{name}".replace(" ", "_"),
                                           DEM_RHO)
            store.write_text(json.dumps(records, indent=1))
    return records


def dem_rates(out: Path, table, c0: float, s2: float) -> None:
    """--dem: mild steel at DEM strain rates (DEM_SPHERE, R 2 mm, 0.03-0.3 m/s: 28-278 v_Y, 44-135 /s, R to
    2.3), each rate law of DEM_RATE_LAWS, on the impact's default mesh: the law's R, the FE's e, the law's e
    error, the base law's (against the rate-independent FE), c_e and PLASTIC-Q's error (c0, s^2 as fitted)."""
    records = dem_records(out)
    specimen = Specimen(*DEM_SPHERE[0:2], DEM_SPHERE[3], DEM_RHO)
    base = table_law(specimen, DEM_SPHERE[2], table)
    print(f"\nDEM strain rates: {DEM_NAME}; e error % of the law (c {RATE_LENGTH_FACTOR:g}) and of PLASTIC-Q:")
    print("| rate law | v_in m/s | eps_dot /s | R | FE e | law e err % | base law err % | c_e | PLASTIC-Q err % |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, (kind, constant, fixed) in DEM_RATE_LAWS.items():
        for v, fe, fe_independent in zip(DEM_SPEEDS, records[name], records["independent"]):
            def e_at(c):
                law = rate_params(specimen, table, kind, DEM_SPHERE[2], constant, fixed, c)
                return float(predict(law, [v])["e"][0])
            params = rate_params(specimen, table, kind, DEM_SPHERE[2], constant, fixed)
            rate = float(params.strain_rate([v])[0])
            e0 = float(collision_reference(BASE_LAWS_LAW["vz-table"], base, [v]).restitution[0])
            eq = plastic_q_e(DEM_SPHERE, table, rate_fit.rate_law(kind, constant, fixed), v, c0, s2, DEM_RHO)
            print(f"| {name} | {v:g} | {rate:.3g} | {float(params.rate_factor([v])[0]):.3f} | {fe:.4f} | "
                  f"{100 * (e_at(RATE_LENGTH_FACTOR) / fe - 1):+.2f} | {100 * (e0 / fe_independent - 1):+.2f} | "
                  f"{root_c(lambda c: e_at(c), fe):.3g} | {100 * (eq / fe - 1):+.2f} |")


def root_c(function, target):
    """The c in C_BRACKET with function(c) = target, or nan where none is."""
    low, high = (function(c) - target for c in C_BRACKET)
    return brentq(lambda c: function(c) - target, *C_BRACKET, xtol=1e-6) if low * high < 0.0 else float("nan")


def main_(out: Path, fine: bool, dem: bool) -> None:
    records = fe_records(out, fine)
    table = VZMasterTable.load(None)
    ref = MATERIALS["reference"]
    v_ref = 12.0 * pair_of(ref).v_Y
    fitted = {variant: root_c(lambda c: variant_e(ref, table, RATE_LAWS[law], v_ref, c, variant),
                              records["reference"][law][1]) for variant, law in FITTED_ON.items()}
    print(f"c = {RATE_LENGTH_FACTOR:g} (the law); the variants' c fitted on the reference at 12 v_Y: "
          + ", ".join(f"{variant} {fitted[variant]:.4g} ({law})" for variant, law in FITTED_ON.items()))
    print("| sphere | rate law | v_in m/s | R (c 26) | FE e | law e err % | base law err % | c_e | c_rate "
          "| SELF e err % | PLASTIC R | PLASTIC e err % |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, laws in records.items():
        material = MATERIALS["reference" if name == "reference fine" else name]
        E, nu, sigma_y, R = material
        pair = pair_of(material)
        specimen = Specimen(E, nu, R, RHO)
        base = table_law(specimen, sigma_y, table)
        for law, fe in laws.items():
            rate = RATE_LAWS[law]
            if rate is None:
                continue
            indep_fe = records.get(name, {}).get("independent") or records["reference"]["independent"]
            for k, m in enumerate(MULTIPLES):
                v = m * pair.v_Y
                params = rate_params(specimen, table, "cowper-symonds", sigma_y, rate[0], rate[1])
                factor = float(params.rate_factor([v])[0])
                e = law_e(material, table, rate, v, RATE_LENGTH_FACTOR)
                e0 = float(collision_reference(BASE_LAWS_LAW["vz-table"], base, [v]).restitution[0])
                c_e = root_c(lambda c: law_e(material, table, rate, v, c), fe[k])
                c_rate = root_c(lambda c: law_e(material, table, rate, v, c) / e0, fe[k] / indep_fe[k])
                es = variant_e(material, table, rate, v, fitted["SELF"], "SELF")
                plastic_r = variant_factor(base, CowperSymonds(*rate), v, fitted["PLASTIC"], "PLASTIC")
                ep = variant_e(material, table, rate, v, fitted["PLASTIC"], "PLASTIC")
                print(f"| {name} | {law} | {v:.4g} | {factor:.3f} | {fe[k]:.4f} | {100 * (e / fe[k] - 1):+.2f} | "
                      f"{100 * (e0 / indep_fe[k] - 1):+.2f} | {c_e:.3g} | {c_rate:.3g} | "
                      f"{100 * (es / fe[k] - 1):+.2f} | {plastic_r:.3f} | {100 * (ep / fe[k] - 1):+.2f} |")
    c0, s2 = plastic_q(records, table)
    if dem:
        dem_rates(out, table, c0, s2)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=None, help="folder for the FE runs and their records (default: a temporary "
                                                    "one)")
    parser.add_argument("--fine", action="store_true", help="add one finer-mesh FE point")
    parser.add_argument("--dem", action="store_true", help="add mild steel at DEM strain rates (R 2 mm, 0.03-0.3 m/s, "
                                                           "Cowper-Symonds and Johnson-Cook)")
    args = parser.parse_args()
    warnings.simplefilter("ignore", RangeWarning)
    if args.out is None:
        with tempfile.TemporaryDirectory() as folder:
            main_(Path(folder), args.fine, args.dem)
    else:
        Path(args.out).mkdir(parents=True, exist_ok=True)
        main_(Path(args.out), args.fine, args.dem)
