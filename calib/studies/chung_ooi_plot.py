"""chung_ooi.png: the Chung & Ooi tests against their closed forms (calib.studies.chung_ooi).

Lines: nfdmodel; open circles: the LAMMPS plugin; crosses: LAMMPS's granular; dashed: gross
sliding; dotted: the no-slip Mindlin spring (scipy); squares: the paper's curves of test 4 as digitised
(calib.studies.chung_ooi_paper; black: one curve for both materials); grey: the plastic vz law.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from calib import output

COLOURS = ("tab:blue", "tab:orange")


def _frame(entry: dict, contact: str | None):
    """(v_n', v_t', omega_i') of a run in the frame of nfdmodel's normal at parting."""
    model = entry["nfdmodel"]
    v = model["velocities"] if contact is None else entry["lammps"][contact]["velocities"]
    turn = model.get("normal_turn", np.zeros(v.shape[0]))
    n = np.stack([np.sin(turn), np.zeros_like(turn), np.cos(turn)], axis=1)
    t = np.stack([np.cos(turn), np.zeros_like(turn), -np.sin(turn)], axis=1)
    relative = v[:, 0] - v[:, 1]
    return np.einsum("ij,ij->i", relative, n), np.einsum("ij,ij->i", relative, t), v[:, 2, 1]


def _series(ax, entry, colour, x, quantity, label):
    """nfdmodel's line and LAMMPS's markers of quantity(v_n', v_t', omega') against x."""
    ax.plot(x, quantity(*_frame(entry, None)), color=colour, lw=1.2, label=label)
    for contact, marker in (("nfd/hertz", "o"), ("granular", "x"), ("nfd/vz", "o")):
        if contact in entry.get("lammps", {}):
            ax.plot(x, quantity(*_frame(entry, contact)), marker, color=colour, ms=4, mfc="none")


def _paper_points(ax, paper: list[dict], quantity: str, materials: list[str], sign: float = 1.0) -> None:
    """The digitised points of ``quantity``, coloured by material (black: the source's single curve)."""
    for colour, material in list(zip(COLOURS, materials)) + [("k", None)]:
        points = [(r["angle"], r["paper"]) for r in paper if r["quantity"] == quantity and (
            r["material"] == material and r["paper_material"] != "either" if material else
            r["paper_material"] == "either" and r["material"] == materials[0])]
        if points:
            angle, value = np.array(points).T
            ax.plot(angle, sign * value, "s", color=colour, ms=4, mfc="none",
                    label="Chung & Ooi (digitised)" if material is None or colour == COLOURS[0] else None)


def plot(path: Path, elastic: list[dict], plastic: list[dict], paper: list[dict] = ()) -> Path:
    plt = output.pyplot()
    fig, axes = plt.subplots(3, 3, figsize=(15, 12))
    by_test = {}
    for entry in elastic:
        by_test.setdefault(entry["case"].test, []).append(entry)
    # tests 1-2: the Hertz closed forms
    ax = axes[0, 0]
    labels, values = [], []
    for test in (1, 2):
        for entry in by_test[test]:
            model, ref = entry["nfdmodel"], entry["reference"]
            for key, name in (("delta_max", "delta_max"), ("P_max", "F_max"), ("contact_time", "t_c")):
                labels.append(f"{test} {entry['case'].material[:5]} {name}")
                values.append(abs(model[key][0] / ref[name][0] - 1.0))
    ax.barh(labels, values, color="tab:blue")
    ax.set_xscale("log")
    ax.set_xlabel("|nfdmodel / Hertz closed form - 1|")
    ax.set_title("tests 1, 2: elastic normal impacts")
    ax.tick_params(axis="y", labelsize=7)
    # test 3
    ax = axes[0, 1]
    for colour, entry in zip(COLOURS, by_test[3]):
        case = entry["case"]
        _series(ax, entry, colour, case.restitution, lambda vn, vt, w, v=case.speed * 1.0: vn / v,
                case.material)
    ax.plot([0, 1], [0, 1], "k:", lw=0.8, label="e out = e in")
    ax.set_xlabel("restitution asked (damping coeff_restitution)")
    ax.set_ylabel("e_n measured")
    ax.set_title("test 3: damped normal impacts")
    ax.legend(fontsize=7)
    # test 4: e_t and omega'
    for ax, key in ((axes[0, 2], "e_t"), (axes[1, 0], "omega")):
        for colour, entry in zip(COLOURS, by_test[4]):
            case, ref = entry["case"], entry["reference"]
            v_t = case.speed * np.sin(np.radians(case.angle))
            if key == "e_t":
                _series(ax, entry, colour, case.angle, lambda vn, vt, w, v_t=v_t: vt / v_t, case.material)
                ax.plot(case.angle, ref["v_t_out_sliding"] / v_t, "--", color=colour, lw=0.8)
                ax.plot(case.angle, 1.0 - (1.0 + ref["beta_no_slip"]) / 3.5, ":", color=colour, lw=0.8)
            else:
                _series(ax, entry, colour, case.angle, lambda vn, vt, w: w, case.material)
                ax.plot(case.angle, ref["omega_out_sliding"], "--", color=colour, lw=0.8)
        materials = [entry["case"].material for entry in by_test[4]]
        if key == "e_t":
            _paper_points(ax, paper, "e_t", materials)
        else:       # the paper draws -omega' (module doc of chung_ooi_paper)
            _paper_points(ax, paper, "spin_rad_s", materials, sign=-1.0)
        ax.set_xlabel("incidence angle [deg]")
        ax.set_ylabel("e_t = v_t'/v_t" if key == "e_t" else "spin out [rad/s]")
        ax.set_ylim(*((0.0, 1.2) if key == "e_t" else ax.get_ylim()))
        ax.set_title(f"test 4: constant speed 3.9 m/s, mu = 0.092 ({key})")
        ax.legend(fontsize=7)
    # test 5: normalised recoil against incidence of the contact point
    ax = axes[1, 1]
    for colour, entry in zip(COLOURS, by_test[5]):
        case, ref = entry["case"], entry["reference"]
        v_n = case.speed * np.cos(np.radians(case.angle))
        psi = case.values
        _series(ax, entry, colour, psi, lambda vn, vt, w, v_n=v_n, R=case.R, mu=case.mu: (vt - R * w) / (mu * v_n),
                case.material)
        ax.plot(psi, psi - 7.0, "--", color=colour, lw=0.8)
        ax.plot(psi, -ref["beta_no_slip"] * psi, ":", color=colour, lw=0.8)
    ax.set_ylim(-6, 8)
    ax.set_xlabel("V/(mu v_n) in (contact point)")
    ax.set_ylabel("V'/(mu v_n) out")
    ax.set_title("test 5: v_n = 5 m/s, mu = 0.3")
    ax.legend(fontsize=7)
    # test 6 and 8: tangential rebound of a spinning sphere
    for ax, test in ((axes[1, 2], 6), (axes[2, 0], 8)):
        for colour, entry in zip(COLOURS, by_test[test]):
            case, ref = entry["case"], entry["reference"]
            v_n = case.speed * np.cos(np.radians(case.angle))
            _series(ax, entry, colour, case.values, lambda vn, vt, w, v_n=v_n: -vt / v_n, case.material)
            ax.plot(case.values, -ref["v_t_out_sliding"] / v_n, "--", color=colour, lw=0.8)
        ax.set_xlabel("omega R / v_n")
        ax.set_ylabel("-v_t' / v_n (relative)")
        ax.set_title(f"test {test}: " + ("spinning sphere on a flat" if test == 6 else "on a sphere 5 R, 1000 rho"))
        ax.legend(fontsize=7)
    # test 7
    ax = axes[2, 1]
    for colour, entry in zip(COLOURS, by_test[7]):
        case = entry["case"]
        _series(ax, entry, colour, case.values, lambda vn, vt, w, om=case.omega: w / om - 1.0, case.material + " spin")
        _series(ax, entry, colour, case.values, lambda vn, vt, w, v=case.speed: vt / v, case.material + " v_t'")
    ax.set_xscale("log")
    ax.set_xlabel("omega [rad/s] (and -omega)")
    ax.set_ylabel("omega'/omega - 1, v_t'/v")
    ax.set_title("test 7: spins omega, -omega (no slip)")
    ax.legend(fontsize=7)
    # plastic: e_t against Psi = tan / (mu (1 + e_n)), and e_n against the angle
    ax = axes[2, 2]
    for shade, entry in zip((0.75, 0.5, 0.2), plastic):
        case, model = entry["case"], entry["nfdmodel"]
        psi = np.tan(np.radians(case.angle)) / (case.mu * (1.0 + model["e_n"]))
        keep = case.angle > 0
        ax.plot(psi[keep], model["e_t"][keep], "o-", color=str(shade), ms=3,
                label=f"vz {case.speed[0]:g} m/s: e_n {model['e_n_head_on'][0]:.3f}")
        if "lammps" in entry:
            v = entry["lammps"]["nfd/vz"]["velocities"][keep]
            v_t = (case.speed * np.sin(np.radians(case.angle)))[keep]
            ax.plot(psi[keep], v[:, 0, 0] / v_t, "o", color="tab:red", ms=5, mfc="none")
    grid = np.linspace(1.0, 12.0, 100)
    ax.plot(grid, 1.0 - 1.0 / grid, "k--", lw=0.8, label="gross sliding 1 - 1/Psi")
    ax.set_xscale("log")
    ax.set_xlabel("Psi = tan(angle) / (mu (1 + e_n))")
    ax.set_ylabel("e_t")
    ax.set_title("plastic vz, mu = 0.3 (Wu, Thornton & Li 2009)")
    ax.legend(fontsize=7)
    fig.suptitle("Chung & Ooi (2011) tests 1-8, elastic limit: nfdmodel (lines), plugin (circles), granular "
                 "(crosses), closed forms (dashed: gross sliding, dotted: no slip)")
    fig.tight_layout()
    output.save_figure(fig, path)
    plt.close(fig)
    return path
