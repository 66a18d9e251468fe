"""Ensembles: rows in the order given, the same bits on any number of threads and as single
runs, DataFrames in and out, a failed case a row with its error."""

import numpy as np
import pandas as pd
import pytest

from hamel.models import MobileRobot


def test_rows_in_order_and_equal_to_single_runs():
    robot = MobileRobot()
    cases = pd.DataFrame({"m0": [8.0, 10.0, 12.0, 14.0], "alpha": [0.1, 0.2, 0.3, 0.4],
                          "w4": [0.5, 0.5, 0.4, 0.3]})
    table = robot.ensemble(cases, t_end=2.0, threads=2)
    assert len(table) == 4 and list(table.cases) == [0, 1, 2, 3]
    assert table.columns[:3] == ("m0", "alpha", "w4")
    for i, row in cases.iterrows():
        model = robot.with_parameters(m0=row.m0)
        run = model.simulate(model.state(alpha=row.alpha, w4=row.w4), t_end=2.0)
        for name in robot.state_names:
            assert table["final_" + name][i] == run[name][-1]
        assert table["steps"][i] == run.summary.steps


def test_the_same_bits_on_one_thread_and_two():
    robot = MobileRobot()
    n = 64
    rng = np.random.default_rng(7)
    states = np.zeros((n, 8))
    states[:, 2] = rng.uniform(-0.5, 0.5, n)
    states[:, 6] = rng.uniform(0.0, 1.0, n)
    parameters = {"m0": rng.uniform(5.0, 15.0, n)}
    one = robot.ensemble(parameters=parameters, states=states, t_end=1.0, threads=1)
    two = robot.ensemble(parameters=parameters, states=states, t_end=1.0, threads=2)
    assert one.columns == two.columns
    for name in one.columns:
        assert np.array_equal(one[name], two[name], equal_nan=True)


def test_a_failed_case_keeps_its_row_and_error():
    robot = MobileRobot()
    table = robot.ensemble(parameters={"m0": [10.0, float("nan"), 10.0]},
                           states={"w4": [0.5, 0.5, 0.5]}, t_end=1.0)
    assert table.failed == 1
    assert table.errors[0] is None and table.errors[2] is None
    kind, message = table.errors[1]
    assert kind == "invalid_parameter" and "`m0` is NaN" in message
    assert np.isnan(table["final_x"][1]) and table["final_x"][0] == table["final_x"][2]
    frame = table.to_pandas()
    assert frame.columns[0] == "case_index" and frame["case_index"].tolist() == [0, 1, 2]
    assert frame["error_kind"].isna().tolist() == [True, False, True]
    assert frame["error_kind"][1] == "invalid_parameter"
    assert frame.shape[0] == 3
    # Means skip the failed case, in pandas as in Arrow, where its outputs are null.
    assert frame["final_x"].mean() == table["final_x"][0]
    arrow = table.to_arrow()
    assert arrow.num_rows == 3 and arrow.column_names[0] == "case_index"
    assert arrow.column("final_x").null_count == 1 and not arrow.column("final_x")[1].is_valid
    # The failed case keeps the values it was given.
    assert arrow.column("w4")[1].as_py() == 0.5
    # Its CSV row: its NaN values empty, as Rust writes them.
    lines = table.to_csv().splitlines()
    assert lines[0].startswith("case_index,m0,w4,final_x,")
    assert lines[2].startswith("1,,0.5,,")


def test_a_table_saved_as_csv_gets_its_manifest(tmp_path):
    robot = MobileRobot()
    table = robot.ensemble(parameters={"m0": [10.0, float("nan")]}, states={"w4": [0.5, 0.5]},
                           t_end=1.0)
    path = tmp_path / "robots.csv"
    assert table.to_csv(path) is None
    assert path.read_text() == table.to_csv()
    manifest = (tmp_path / "robots.csv.manifest").read_text().splitlines()
    assert manifest[0] == "hamel file manifest 1"
    assert "rows 2" in manifest and f"bytes {path.stat().st_size}" in manifest
    back = pd.read_csv(path)
    assert back.columns[0] == "case_index" and back["final_x"].isna().tolist() == [False, True]


def test_event_columns_and_samples():
    import hamel

    robot = MobileRobot()
    table = robot.ensemble(states={"alpha": [0.3, 0.3], "w4": [0.5, 0.5], "w5": [0.4, -0.4]},
                           t_end=10.0, events=[hamel.Event("half", state="alpha", value=3.0)],
                           sample_at=[5.0])
    assert "half_first" in table.columns and "half_count" in table.columns
    assert "x@5" in table.columns


def test_bad_cases_name_the_column():
    robot = MobileRobot()
    with pytest.raises(ValueError, match="cases: the column 'mass' is neither a parameter"):
        robot.ensemble(pd.DataFrame({"mass": [1.0]}))
    with pytest.raises(ValueError, match="columns of different lengths"):
        robot.ensemble(parameters={"m0": [1.0, 2.0]}, states={"w4": [0.5]})
    with pytest.raises(ValueError, match="threads: at least 1"):
        robot.ensemble(parameters={"m0": [1.0]}, threads=0)
