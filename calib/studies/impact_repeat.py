"""Repeated impacts on one spot: the dynamic FE's series (calib.fe.impact_repeat) beside the laws'
(nfdmodel.collide_repeated), e of each impact.

Per velocity, one FE series of N impacts of the sphere on the rigid flat at v_in, each starting
from the last one's residual state (the dent and residual stresses carried over, the vibrations
let die out: calib.fe.impact_repeat), on the impact's mesh (calib.studies.impact.impact_mesh)
with its refined zone widened by REFINED_ZONE_FACTOR (the later impacts reach a higher P_max and
a wider contact). Beside each FE impact, the same impact k of the laws given, their contact's
history carried over: vz (the master table's constants or --params'), vz-table (--table-params)
and vz-unload (--unload-params); per law e_law and e_law / e_FE - 1.

Writes OUT/repeat.json (the records and a stamp) and OUT/repeat.csv (one row per impact).
Units: SI.
"""
from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import Callable

from calib import output
from calib.fe.elastic import ElasticMaterial
from calib.fe.impact_repeat import repeated_impacts
from calib.fe.newmark import ImpactSolver
from calib.fe.von_mises import von_mises_material
from calib.studies.impact import ImpactSetup, impact_mesh
from calib.studies.impact_files import check_material
from meshes.sphere import sphere_mesh
from nfdmodel import collide_repeated

REFINED_ZONE_FACTOR = 1.5        # the refined zone's radius x the first impact's mesh's (the later impacts reach further)
MAX_REPEAT = 10                  # impacts per velocity through nfdcal impact --repeat


def unload_parameters(setup: ImpactSetup, path):
    """The vz-unload law's parameters of ``path``; a ValueError naming --unload-params for a file of
    another law or material (calib.studies.impact_files.check_material)."""
    from nfdmodel import VZUnloadParams, load_parameters
    from nfdmodel.parameter_file import law_of

    try:
        params = load_parameters(path)
    except (ValueError, OSError) as exc:
        raise ValueError(f"--unload-params {path}: {exc}") from None
    if not isinstance(params, VZUnloadParams):
        raise ValueError(f"--unload-params {path}: holds the {law_of(params)} law, not the vz-unload law: give a"
                         f" vz-unload file (nfdcal calibrate --ship unload)")
    check_material(setup, path, "--unload-params")
    return params


def series_mesh(setup: ImpactSetup, v_in: float):
    """The sphere mesh spec of a series at v_in [m/s] (module docstring)."""
    spec = impact_mesh(setup, v_in)
    return dataclasses.replace(spec, refined_radius=REFINED_ZONE_FACTOR * spec.refined_radius)


def fe_series(setup: ImpactSetup, v_in: float, repeat: int, progress: Callable[[str], None] | None = None):
    """The FE's ``repeat`` impacts at v_in [m/s] (calib.fe.impact_repeat.RepeatedImpact list) and
    the mesh's description."""
    spec = series_mesh(setup, v_in)
    material = setup.material
    fe_material = (ElasticMaterial(material.E, material.nu) if setup.elastic else
                   von_mises_material(material.E, material.nu, material.sigma_y, setup.hardening, setup.rate_law))
    solver = ImpactSolver(sphere_mesh(spec), fe_material, material.rho)
    return repeated_impacts(solver, v_in, repeat, steps_per_contact=setup.steps_per_contact,
                            progress=progress), spec.describe()


def law_series(laws: dict, v_in: float, repeat: int) -> dict:
    """{law name: [e of impact 1..repeat]} of each law (name -> parameters) at v_in [m/s]."""
    return {name: [float(r.e_velocity[0]) for r in collide_repeated(name, params, [v_in], repeat, dt=None)]
            for name, params in laws.items()}


def study(setup: ImpactSetup, velocities, repeat: int, out: Path, laws: dict, sources: dict,
          progress: Callable[[str], None] | None = None) -> list[dict]:
    """The series at each velocity, the laws beside them; writes OUT/repeat.json and repeat.csv;
    returns one record per impact: v_in, v_in_over_v_Y, repeat, the FE's figures, and per law
    e_<law> and e_<law>_over_fe_minus_1."""
    started = time.perf_counter()
    records, meshes = [], {}
    v_Y = setup.pair.v_Y
    for v_in in velocities:
        impacts, mesh = fe_series(setup, v_in, repeat, progress)
        meshes[f"{v_in:g}"] = mesh
        by_law = law_series(laws, v_in, repeat)
        for impact in impacts:
            record = {"v_in": float(v_in), "v_in_over_v_Y": float(v_in / v_Y), **impact.record()}
            for name, es in by_law.items():
                e_law = es[impact.repeat - 1]
                record[f"e_{name}"] = e_law
                record[f"e_{name}_over_fe_minus_1"] = e_law / impact.e - 1.0
            records.append(record)
    stamp = output.stamp(time.perf_counter() - started, meshes=meshes, laws=sources, repeat=repeat)
    out.mkdir(parents=True, exist_ok=True)
    output.write_json(out / "repeat.json", {"stamp": stamp, "records": records})
    output.write_csv(out / "repeat.csv", records)
    return records
