"""Parquet: tables the CLI writes are read by pyarrow with the documented schema; a scans
table pyarrow writes is read by the CLI; the Arrow tables of the bindings equal the CLI's."""

import json

import numpy as np
import pytest

import laserlines
from conftest import EXCERPT

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

F64 = pa.float64()

# The schemas as README.md documents them.
LINES_SCHEMA = pa.schema(
    [
        pa.field("scan", pa.int64(), nullable=False),
        pa.field("stamp", F64),
        pa.field("pose_x", F64),
        pa.field("pose_y", F64),
        pa.field("pose_theta", F64),
    ]
    + [
        pa.field(n, F64, nullable=False)
        for n in ["start_x", "start_y", "end_x", "end_y", "r", "alpha"]
    ]
    + [pa.field(n, pa.int64(), nullable=False) for n in ["first", "last", "points"]]
    + [pa.field(n, F64, nullable=False) for n in ["rms", "cov_rr", "cov_ralpha", "cov_alphaalpha"]]
)
SCANS_SCHEMA = pa.schema(
    [
        pa.field("scan", pa.int64(), nullable=False),
        pa.field("stamp", F64),
        pa.field("pose_x", F64),
        pa.field("pose_y", F64),
        pa.field("pose_theta", F64),
        pa.field("odometry_x", F64),
        pa.field("odometry_y", F64),
        pa.field("odometry_theta", F64),
    ]
    + [
        pa.field(n, F64, nullable=False)
        for n in ["angle_min", "angle_increment", "range_min", "range_max"]
    ]
    + [
        pa.field("ranges", pa.list_(F64), nullable=False),
        pa.field("intensities", pa.list_(F64)),
    ]
)


@pytest.fixture(scope="module")
def written(cli, tmp_path_factory):
    d = tmp_path_factory.mktemp("parquet")
    cli("extract", EXCERPT, "-o", d / "lines.parquet")
    cli("extract", EXCERPT, "-o", d / "lines.jsonl")
    cli("convert", EXCERPT, d / "scans.parquet")
    return d


def test_the_cli_writes_the_documented_schemas(written):
    assert pq.read_schema(written / "lines.parquet").remove_metadata() == LINES_SCHEMA
    assert pq.read_schema(written / "scans.parquet").remove_metadata() == SCANS_SCHEMA
    assert laserlines.lines_schema() == LINES_SCHEMA
    assert laserlines.scans_schema() == SCANS_SCHEMA


def test_lines_parquet_holds_the_lines_of_lines_jsonl(written):
    t = pq.read_table(written / "lines.parquet")
    rows = t.to_pylist()
    expected = []
    for obj in map(json.loads, (written / "lines.jsonl").read_text().splitlines()):
        for line in obj["lines"]:
            expected.append((obj, line))
    assert len(rows) == len(expected) > 100
    for row, (obj, line) in zip(rows, expected):
        assert row["scan"] == obj["scan"] and row["stamp"] == obj["stamp"]
        assert (row["pose_x"], row["pose_y"], row["pose_theta"]) == (
            obj["pose"]["x"],
            obj["pose"]["y"],
            obj["pose"]["theta"],
        )
        assert [row["start_x"], row["start_y"]] == line["start"]
        assert [row["end_x"], row["end_y"]] == line["end"]
        assert (row["r"], row["alpha"], row["rms"]) == (line["r"], line["alpha"], line["rms"])
        assert (row["first"], row["last"], row["points"]) == (
            line["first"],
            line["last"],
            line["points"],
        )
        c = line["covariance"]
        assert (row["cov_rr"], row["cov_ralpha"], row["cov_alphaalpha"]) == (
            c[0][0],
            c[0][1],
            c[1][1],
        )


def test_scans_parquet_holds_the_scans_bit_for_bit(written):
    t = pq.read_table(written / "scans.parquet")
    scans = list(laserlines.read(EXCERPT))
    assert t.num_rows == len(scans) == 40
    for k, s in enumerate(scans):
        row = t.slice(k, 1).to_pylist()[0]
        assert row["scan"] == k and row["stamp"] == s.stamp
        assert (row["pose_x"], row["pose_y"], row["pose_theta"]) == s.pose
        # The excerpt's wheel odometry (BreezySLAM encoders), kept as well.
        assert s.odometry is not None
        assert (row["odometry_x"], row["odometry_y"], row["odometry_theta"]) == s.odometry
        assert row["angle_increment"] == s.angle_increment
        assert np.array_equal(np.array(row["ranges"], dtype=np.float64), s.ranges, equal_nan=True)
        assert row["intensities"] is None
    # Read back by the bindings, as by the CLI: the scans written.
    back = list(laserlines.read(written / "scans.parquet"))
    assert [b.odometry for b in back] == [s.odometry for s in scans]
    for b, s in zip(back, scans):
        assert np.array_equal(b.ranges, s.ranges, equal_nan=True)


def test_a_table_pyarrow_writes_is_read_by_the_cli(cli, tmp_path):
    scans = list(laserlines.read(EXCERPT))[:12]
    # float32 ranges, as sensor_msgs/LaserScan holds them: the reader widens them.
    ranges = [s.ranges.astype(np.float32) for s in scans]
    table = pa.table(
        {
            "scan": pa.array(range(len(scans)), pa.int64()),
            "stamp": [s.stamp for s in scans],
            "pose_x": [s.pose[0] for s in scans],
            "pose_y": [s.pose[1] for s in scans],
            "pose_theta": [s.pose[2] for s in scans],
            "angle_min": [s.angle_min for s in scans],
            "angle_increment": [s.angle_increment for s in scans],
            "range_min": [s.range_min for s in scans],
            "range_max": [s.range_max for s in scans],
            "ranges": pa.array(ranges, pa.list_(pa.float32())),
            "intensities": pa.nulls(len(scans), pa.list_(pa.float32())),
        }
    )
    # The documented columns but the optional odometry (a table without it reads as scans
    # without odometry), ranges as float32; pyarrow makes every column nullable.
    assert [f.name for f in table.schema] == [
        f.name for f in SCANS_SCHEMA if not f.name.startswith("odometry_")
    ]
    assert table.schema.field("ranges").type == pa.list_(pa.float32())
    path = tmp_path / "from-pyarrow.parquet"
    pq.write_table(table, path)  # pyarrow's defaults: snappy, nullable columns
    out = tmp_path / "lines.jsonl"
    run = cli("extract", path, "-o", out)
    assert ": 12 scans" in run.stderr
    got = [json.loads(line) for line in out.read_text().splitlines()]
    ex = laserlines.Extractor()
    for s, r, g in zip(scans, ranges, got):
        lines = ex.extract(r.astype(np.float64), s.angle_min, s.angle_increment, s.range_min, s.range_max)
        assert g["stamp"] == s.stamp
        assert [line["r"] for line in g["lines"]] == lines["r"].tolist()
        assert [line["first"] for line in g["lines"]] == lines["first"].tolist()


def test_arrow_tables_of_the_bindings_equal_the_cli(cli, written, tmp_path):
    from_file = laserlines.extract_file(EXCERPT)
    assert from_file.schema == LINES_SCHEMA
    assert from_file.equals(pq.read_table(written / "lines.parquet").replace_schema_metadata(None))
    scans = pq.read_table(written / "scans.parquet")
    cli("extract", written / "scans.parquet", "-o", tmp_path / "from-scans.parquet")
    from_table = laserlines.Extractor().extract_table(scans)
    expected = pq.read_table(tmp_path / "from-scans.parquet").replace_schema_metadata(None)
    assert from_table.equals(expected)
    # Batches of the table give the same rows (scan indices come from the table).
    parts = [laserlines.Extractor().extract_table(pa.Table.from_batches([b])) for b in scans.to_batches(max_chunksize=7)]
    assert pa.concat_tables(parts).equals(expected)


def test_inf_range_max_in_a_table_is_no_limit():
    scan = next(iter(laserlines.read(EXCERPT)))
    table = pa.table(
        {
            "angle_min": [scan.angle_min],
            "angle_increment": [scan.angle_increment],
            "range_min": [scan.range_min],
            "range_max": [float("inf")],
            "ranges": pa.array([scan.ranges.astype(np.float32)], pa.list_(pa.float32())),
        }
    )
    lines = laserlines.Extractor().extract_table(table)
    ranges = scan.ranges.astype(np.float32).astype(np.float64)
    expected = laserlines.extract(ranges, scan.angle_min, scan.angle_increment, scan.range_min)
    assert lines.column("r").to_pylist() == expected["r"].tolist()
