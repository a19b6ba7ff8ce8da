"""The collision report's section of results/README.md (calib.report.results_index): the runtime laws'
restitution and time-step convergence, read from results/collision/summary.json (``nfdcal collide --report``,
calib.report.collision).
"""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import g, num, read_json, section, table


def collision(root: Path) -> list[str]:
    folder = root / "collision"
    data = read_json(folder / "summary.json")
    if data is None:
        return []
    case, vz, th = data["case"], data["restitution_vz"], data["restitution_thornton"]
    window = data["vz_window"]
    command = data["stamp"].get("command", "nfdcal collide --report")
    if data["params_source"].endswith(".json") and "--params" not in command:
        command += f" --params {data['params_source']}"     # the file the report read: no implicit read
    lines = section("Collisions of the runtime laws (`collision/`)", folder, root, command, data["stamp"])
    lines += [f"Sphere on a rigid flat: R = {case['R']:g} m, mass {g(case['mass'])} kg, P_Y = {g(case['P_Y'])} N, "
              f"a_Y = {g(case['a_Y'])} m, delta_Y = {g(case['delta_Y'])} m, v_Y = {g(case['v_Y'])} m/s, "
              f"A_Y = {case['A_Y']:.5g}; vz constants from `{data['params_source']}` (Ca = {g(case['Ca'])} m/N, "
              f"Kc = {g(case['Kc'])} 1/N), window to {window['P_max_over_P_Y']:.3g} P_Y; dt = {vz['dt']:g} s.", ""]
    rows = [[f"{v:g}", f"{v / case['v_Y']:.1f}", f"{ev:.4f}", f"{et:.4f}", "yes" if inside else "no"]
            for v, ev, et, inside in zip(vz["v_in"], vz["e_velocity"], th["e_velocity"],
                                         window["in_calibrated_range"])]
    lines += table(["v_in [m/s]", "v_in / v_Y", "e, vz", "e, thornton", "vz inside its window"], rows)
    tc = data["thornton_closed_form_check"]
    lines += [f"e from velocities against e from energies: within {g(vz['max_relative_difference_e_velocity_e_energy'], 2)}"
              f" (vz), {g(th['max_relative_difference_e_velocity_e_energy'], 2)} (thornton); against the exact "
              f"energy balance: {g(vz['max_relative_error_vs_exact'], 2)}, {g(th['max_relative_error_vs_exact'], 2)}; "
              f"Thornton's closed form (paper eq. 1.11): {g(tc['max_relative_error'], 2)}.", ""]
    impact = data.get("impact_vz_v0.04")
    if impact:
        lines += [f"The vz impact at 0.04 m/s: P_max = {g(impact['P_max'])} N, delta_max = {g(impact['delta_max'])} m, "
                  f"residual {g(impact['delta_res'])} m, contact time {g(impact['contact_time'])} s.", ""]
    dt_rows = [[r["law"], f"{r['dt']:g}", r["steps"], g(r["error_e_velocity"], 2), g(r["error_P_max"], 2),
                num(r["wall_time_s"] * 1e3)] for r in data["dt_convergence"]]
    lines += ["Time-step convergence (largest error over the sweep's velocities, `dt_convergence.csv`):", ""]
    lines += table(["law", "dt [s]", "steps", "e error", "P_max error", "wall [ms]"], dt_rows)
    return lines
