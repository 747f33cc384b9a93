"""legkit.io: the log format from Python, against the file's own text and the C++ reader."""
import csv
import subprocess

import numpy as np
import pytest

import legkit
from conftest import ICUB_LOG, LEGKIT


def test_columns_are_the_files_numbers_exactly():
    log = legkit.io.read_log(str(ICUB_LOG))
    with open(ICUB_LOG) as f:
        lines = [line for line in f if not line.startswith("#")]
    table = list(csv.reader(lines))
    header, rows = table[0], table[1:]
    assert len(log) == len(rows) > 1000
    assert log.layout.num_joints > 0 and log.layout.ground_truth and not log.layout.joints
    assert set(log.columns) == set(name.strip() for name in header)
    for c, name in enumerate(header):
        expected = np.array([float(r[c]) for r in rows])
        assert np.array_equal(log[name.strip()], expected), name
    assert log.source == str(ICUB_LOG)
    assert log.line_of_row(0) == len(log.comments) + 2


def test_write_then_read_is_exact(tmp_path, trot_log):
    path = tmp_path / "trot.csv"
    legkit.io.write_log(str(path), trot_log)
    again = legkit.io.read_log(str(path))
    assert again.layout == trot_log.layout
    a, b = trot_log.to_dict(), again.to_dict()
    assert list(a) == list(b)
    for name in a:
        assert np.array_equal(a[name], b[name]), name


def test_from_columns_gives_back_the_same_log(trot_log):
    columns = trot_log.to_dict()
    made = legkit.io.Log.from_columns(columns, comments=["made in Python"])
    assert made.layout == trot_log.layout and made.comments == ["made in Python"]
    for name, values in columns.items():
        assert np.array_equal(made[name], values), name


def test_simulated_log_is_the_one_legkit_sim_writes(tmp_path):
    path = tmp_path / "sim.csv"
    subprocess.run([str(LEGKIT), "sim", "--scenario", "walk", "--duration", "1", "--seed", "3",
                    "--out", str(path)], check=True, capture_output=True)
    cli = legkit.io.read_log(str(path)).to_dict()
    py = legkit.sim.simulate("walk", duration=1.0, seed=3).to_dict()
    assert list(cli) == list(py)
    for name in cli:
        assert np.array_equal(cli[name], py[name]), name


def test_a_bad_file_names_file_line_and_column(tmp_path, trot_log):
    path = tmp_path / "bad.csv"
    legkit.io.write_log(str(path), trot_log)
    lines = path.read_text().splitlines()
    header = lines[len(trot_log.comments)].split(",")
    row = len(trot_log.comments) + 1 + 10  # the 11th row
    fields = lines[row].split(",")
    fields[header.index("acc_y")] = "nan"
    lines[row] = ",".join(fields)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(legkit.io.LogError, match=r"bad.csv:\d+: column 'acc_y'") as error:
        legkit.io.read_log(str(path))
    assert error.value.file == str(path)
    assert error.value.line == row + 1
    assert error.value.column == "acc_y"
    assert isinstance(error.value, ValueError)


def test_missing_file_and_gap_bound():
    with pytest.raises(legkit.io.LogError, match="cannot open"):
        legkit.io.read_log("/nonexistent/log.csv")
    with pytest.raises(legkit.io.LogError, match="gap|step"):
        legkit.io.read_log(str(ICUB_LOG), max_gap=1e-4)


def test_from_columns_refuses_what_a_file_could_not_hold(trot_log):
    columns = trot_log.to_dict()
    short = dict(columns, gyro_x=columns["gyro_x"][:-1])
    with pytest.raises(ValueError, match="gyro_x.* rows"):
        legkit.io.Log.from_columns(short)
    with pytest.raises(TypeError, match="expected numbers"):
        legkit.io.Log.from_columns(dict(columns, gyro_x=np.array(["a"] * len(trot_log))))
    nan = dict(columns, gyro_y=columns["gyro_y"].copy())
    nan["gyro_y"][7] = np.nan
    with pytest.raises(legkit.io.LogError, match=r"<from_columns>:9: column 'gyro_y'"):
        legkit.io.Log.from_columns(nan)
    missing = {k: v for k, v in columns.items() if k != "acc_z"}
    with pytest.raises(legkit.io.LogError, match="acc_z"):
        legkit.io.Log.from_columns(missing)
    with pytest.raises(KeyError, match="no column 'force_XX'"):
        trot_log["force_XX"]
