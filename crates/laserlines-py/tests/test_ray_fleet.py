"""examples/ray_fleet.py on a local Ray (2 CPUs) over a few logs: MCAP (foxglove.LaserScan as
`laserlines convert` writes it, ROS 2 CDR) and Parquet scans tables. Every scan is read (the
scan count of each log equals the CLI's), and the lines equal the CLI's for the same scans.

Skipped with a notice when Ray is not installed, unless LASERLINES_REQUIRE_RAY=1 (CI)."""

import os
import pathlib
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import EXCERPT, FIXTURES, REPO

if os.environ.get("LASERLINES_REQUIRE_RAY") == "1":
    import ray  # noqa: F401  (CI: Ray must be there)
else:
    pytest.importorskip("ray", reason="Ray is not installed: pip install 'ray[data]' to run the fleet example")
pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

GEOMETRY = ["start_x", "start_y", "end_x", "end_y", "r", "alpha", "first", "last", "points", "rms",
            "cov_rr", "cov_ralpha", "cov_alphaalpha"]
CARMEN = REPO / "crates" / "laserlines-io" / "tests" / "fixtures" / "carmen" / "wall_param.clf"


@pytest.fixture(scope="module")
def fleet(cli, tmp_path_factory):
    """A folder of logs, the example's output over it, and what it printed."""
    logs = tmp_path_factory.mktemp("fleet") / "logs"
    (logs / "robot-b").mkdir(parents=True)
    cli("convert", EXCERPT, logs / "exp1-scans.parquet")
    cli("convert", EXCERPT, logs / "robot-b" / "exp1.mcap")
    cli("convert", CARMEN, logs / "robot-b" / "wall-scans.parquet")
    shutil.copy(FIXTURES / "ros2_laserscan.mcap", logs / "ros2.mcap")
    out = logs.parent / "lines"
    run = subprocess.run(
        [sys.executable, str(REPO / "examples" / "ray_fleet.py"), str(logs), "-o", str(out),
         "--num-cpus", "2", "--workers", "1", "--topic", "/scan", "--count-scans"],
        capture_output=True, text=True, timeout=600,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    return logs, pq.read_table(out), run.stderr


def logs_of(logs):
    return sorted(p for p in logs.rglob("*") if p.suffix in (".mcap", ".parquet"))


def test_every_scan_of_every_log_is_read(fleet, cli):
    logs, _, stderr = fleet
    counted = {pathlib.Path(p).name: int(n) for p, n in re.findall(r"^(\S+): (\d+) scans$", stderr, re.M)}
    assert len(counted) == 4
    for log in logs_of(logs):
        run = cli("convert", log, log.with_suffix(".check.jsonl"))
        expected = int(re.search(r": (\d+) scans written", run.stderr).group(1))
        assert counted[log.name] == expected > 0, log.name


def test_lines_equal_the_cli_for_the_same_scans(fleet, cli, tmp_path):
    logs, table, _ = fleet
    total = 0
    for log in logs_of(logs):
        cli("extract", log, "-o", tmp_path / "cli.parquet")
        expected = pq.read_table(tmp_path / "cli.parquet")
        got = table.filter(pa.compute.match_substring(table["path"], log.name))
        assert got.num_rows == expected.num_rows, log.name
        keys = [("stamp", "ascending"), ("first", "ascending")]
        got, expected = got.sort_by(keys), expected.sort_by(keys)
        columns = GEOMETRY + ["stamp"] + (["scan", "pose_x", "pose_y", "pose_theta"] if log.suffix == ".parquet" else [])
        for c in columns:
            assert np.array_equal(got[c].to_numpy(zero_copy_only=False), expected[c].to_numpy(zero_copy_only=False)), (log.name, c)
        total += got.num_rows
    assert total == table.num_rows > 300


def test_lines_name_their_topic_and_a_second_run_into_the_output_is_refused(fleet):
    logs, table, _ = fleet
    topics = dict(zip(table["path"].to_pylist(), table["topic"].to_pylist()))
    for path, topic in topics.items():
        assert topic == ("/scan" if path.endswith(".mcap") else None), (path, topic)
    run = subprocess.run(
        [sys.executable, str(REPO / "examples" / "ray_fleet.py"), str(logs), "-o", str(logs.parent / "lines")],
        capture_output=True, text=True, timeout=600,
    )
    assert run.returncode != 0
    assert "lines: not empty (its files would be read with this run's)" in run.stderr, run.stderr[-2000:]


def test_logs_without_lines_write_nothing_and_say_so(tmp_path):
    # Two scans of 9 and 10 beams: no line in either.
    logs = tmp_path / "logs"
    logs.mkdir()
    shutil.copy(FIXTURES / "foxglove_laserscan.mcap", logs / "tiny.mcap")
    run = subprocess.run(
        [sys.executable, str(REPO / "examples" / "ray_fleet.py"), str(logs), "-o", str(tmp_path / "lines"),
         "--num-cpus", "2", "--workers", "1", "--count-scans"],
        capture_output=True, text=True, timeout=600,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    assert "tiny.mcap: 2 scans" in run.stderr
    assert "1 MCAP and 0 Parquet logs: no lines, nothing written to" in run.stderr, run.stderr[-2000:]
