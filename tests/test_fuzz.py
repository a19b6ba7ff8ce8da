"""The command-line fuzzer (tests/fuzzing.py) in CI: a few hundred derandomized cases, every one a
success or one line with exit code 2; never a traceback, NaN in an output, a file touched outside
the output paths, or a hang; and 40 of collide alone (its oblique models). Thousands more:
tests/benchmarks/fuzz_cli.py.

fit-data's unit factors: a sample of the (data kind, column, factor 1e-3..1e3) cases, each a
sigma_Y whose 95 % interval holds the FE's truth or one line naming the column (every case:
tests/benchmarks/fuzz_cli.py --fit-data; each costs a fit, seconds)."""
import random
import re
import tempfile
from pathlib import Path

import pytest
from fuzzing import command_case, fit_data_argv, fit_data_cases, run_case, run_fit_data_case
from hypothesis import HealthCheck, given, settings

CASES = 250
COLLIDE_CASES = 40


@settings(max_examples=CASES, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(case=command_case())
def test_every_command_line_ends_in_success_or_one_clean_line(case):
    with tempfile.TemporaryDirectory() as sandbox:
        outcome = run_case(case, Path(sandbox), timeout_s=60.0)
    assert not outcome.failed, (f"{outcome.kind}\nargv: {case.argv}\nstdout: {outcome.stdout[-500:]}\n"
                                f"stderr: {outcome.stderr[-1500:]}")


@settings(max_examples=COLLIDE_CASES, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(case=command_case(commands=("collide",)))
def test_collide_oblique_lines_end_in_success_or_one_clean_line(case):
    """collide alone: angles, spins, the damping x tangential x rolling x twisting models, --plot."""
    with tempfile.TemporaryDirectory() as sandbox:
        outcome = run_case(case, Path(sandbox), timeout_s=60.0)
    assert not outcome.failed, (f"{outcome.kind}\nargv: {case.argv}\nstdout: {outcome.stdout[-500:]}\n"
                                f"stderr: {outcome.stderr[-1500:]}")


FIT_DATA_SAMPLE = random.Random(37).sample(fit_data_cases(), 2)


@pytest.mark.parametrize("case", FIT_DATA_SAMPLE, ids=[c.name for c in FIT_DATA_SAMPLE])
def test_fit_data_with_a_column_off_by_a_unit_factor_is_right_or_refused_naming_it(case):
    with tempfile.TemporaryDirectory() as sandbox:
        verdict, outcome = run_fit_data_case(case, Path(sandbox))
    assert not verdict.startswith("FAIL"), (verdict, fit_data_argv(case).argv, outcome.stderr[-800:])
    if verdict == "refused":
        assert re.search(rf"column '?{case.column}\b", outcome.stderr)
