"""`hamel.study` from a DataFrame: the table of the Rust study, in memory and as shards whose
merge is byte for byte the file of one task."""

import numpy as np
import pandas as pd
import pytest

import hamel
from hamel.models import MobileRobot


def cases(n=12):
    rng = np.random.default_rng(3)
    return pd.DataFrame({"m0": rng.uniform(8.0, 12.0, n), "alpha": rng.uniform(0.1, 0.4, n),
                         "w4": np.full(n, 0.5)})


def test_a_study_in_memory_is_the_ensembles_table():
    robot = MobileRobot()
    table = hamel.study(robot, cases(), name="robots", t_end=2.0, threads=2)
    ensemble = robot.ensemble(cases(), t_end=2.0, threads=1)
    assert table.columns == ensemble.columns
    for name in table.columns:
        assert np.array_equal(table[name], ensemble[name], equal_nan=True)
    assert table.columns[:3] == ("m0", "alpha", "w4")


def test_shards_merge_into_the_file_of_one_task(tmp_path):
    robot = MobileRobot()
    for i in range(3):
        assert hamel.study(robot, cases(), name="robots", out=tmp_path / "shards",
                           shard=f"{i}/3", t_end=2.0) is None
    hamel.study(robot, cases(), name="robots", merge=tmp_path / "shards",
                into=tmp_path / "merged.csv", t_end=2.0)
    hamel.study(robot, cases(), name="robots", out=tmp_path / "whole", t_end=2.0)
    whole = list((tmp_path / "whole").glob("*.csv"))
    assert len(whole) == 1
    merged = (tmp_path / "merged.csv").read_bytes()
    assert merged == whole[0].read_bytes()
    frame = pd.read_csv(tmp_path / "merged.csv")
    assert len(frame) == 12 and "final_x" in frame.columns


def test_a_study_names_a_bad_column():
    with pytest.raises(ValueError, match="the column `mass` is neither a parameter"):
        hamel.study(MobileRobot(), {"mass": [1.0]})
