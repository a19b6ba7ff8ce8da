"""The plot of a fit to measurements (``nfdcal fit-data --plot``): the data against the fitted law.

Panel "impacts": measured e against v_in [m/s] (log axis), the fitted law's quasi-static
e(v_in) (nfdmodel.collision_reference) with its 95 % confidence band for the parameters'
uncertainty, e +- 1.96 se(v_in), se^2 = g^T Cov(log theta) g (delta method,
calib.fit.measured.bands.restitution_band), the other model dashed, v_Y marked. Panel
"force-approach": measured force [N] against approach [m] and the fitted law driven along the
same approach. Written atomically through calib.output.save_figure.
"""
from __future__ import annotations

import numpy as np

from calib import output
from calib.fit.measured.bands import restitution_band
from calib.fit.measured.data import Measurements
from calib.fit.measured.models import ModelChoice
from calib.fit.measured.specimen import Specimen, predict_forces, predict_impacts


def plot_fit(path, choice: ModelChoice, data: Measurements, specimen: Specimen, table) -> None:
    """Draw the fit of ``choice`` (the model used, and the other one when fitted) to ``data``."""
    plt = output.pyplot()
    result = choice.result
    other = choice.free if choice.used == "constrained" else choice.constrained
    panels = [p for p, d in (("impacts", data.impacts), ("forces", data.forces)) if d is not None]
    fig, axes = plt.subplots(1, len(panels), figsize=(6.5 * len(panels), 4.8), squeeze=False)
    for ax, panel in zip(axes[0], panels):
        if panel == "impacts":
            impacts = data.impacts
            v = np.geomspace(impacts.v_in.min() / 1.5, impacts.v_in.max() * 1.5, 120)
            e, half_width = restitution_band(result, v, specimen, table)
            ax.fill_between(v, np.clip(e - half_width, 0.0, 1.0), np.clip(e + half_width, 0.0, 1.0),
                            color="C3", alpha=0.25, lw=0, label="95 % band (parameters)")
            ax.plot(v, e, color="C3", label=f"{choice.used} fit")
            if other is not None:
                ax.plot(v, predict_impacts(other.params, v)["e"], "--", color="C7",
                        label=f"{'free' if choice.used == 'constrained' else 'constrained'} fit")
            ax.plot(impacts.v_in, impacts.e, "o", color="k", ms=4, label="drop tests")
            ax.axvline(result.params.pair.v_Y, color="C0", lw=0.8, ls=":", label="v_Y")
            ax.set_xscale("log")
            ax.set_xlabel("v_in [m/s]")
            ax.set_ylabel("restitution e [-]")
            ax.set_title(f"sigma_Y = {result.values['sigma_y'] / 1e6:.4g} MPa, Ca_hat = {result.values['Ca_hat']:.4g}, "
                         f"Kc_hat = {result.values['Kc_hat']:.4g}", fontsize=9)
        else:
            predicted = predict_forces(result.params, data.forces)
            for k, ((label, approach, force), law) in enumerate(zip(data.forces.tests, predicted)):
                ax.plot(approach, force, "o", ms=3, color=f"C{k % 10}", label=f"measured {label}".rstrip())
                ax.plot(approach, law, "-", color=f"C{k % 10}", lw=1)
            ax.plot([], [], "-", color="k", lw=1, label=f"{choice.used} fit")
            ax.set_xlabel("approach [m]")
            ax.set_ylabel("force [N]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    output.save_figure(fig, path)
