"""The result writers: atomic, stamped, and never a NaN in a result file."""
import json
import math

import numpy as np
import pytest

from calib import output


def test_json_roundtrip_converts_numpy(tmp_path):
    path = output.write_json(tmp_path / "a" / "r.json", {"x": np.float64(1.5), "v": np.arange(3)})
    assert json.loads(path.read_text()) == {"x": 1.5, "v": [0, 1, 2]}


def test_json_rejects_nan(tmp_path):
    with pytest.raises(ValueError, match="non-finite"):
        output.write_json(tmp_path / "r.json", {"x": math.nan})
    assert not (tmp_path / "r.json").exists()


def test_csv_has_stamp_comment_and_rows(tmp_path):
    st = output.stamp(1.23, mesh={"h_contact": 1e-5})
    path = output.write_csv(tmp_path / "r.csv", [{"a": 1.0, "b": 2}], comment=output.stamp_comment(st))
    lines = path.read_text().splitlines()
    assert lines[0].startswith("# git_commit:")
    assert "a,b" in lines and "1.0,2" in lines


def test_no_temporary_files_left(tmp_path):
    output.atomic_write_text(tmp_path / "x.txt", "hello")
    assert [p.name for p in tmp_path.iterdir()] == ["x.txt"]
