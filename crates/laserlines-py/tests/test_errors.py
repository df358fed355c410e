"""Bad input raises ValueError or TypeError with a clear message, never a crash."""

import os

import numpy as np
import pytest

import laserlines
from conftest import EXCERPT

GOOD = np.array([1.0, 1.1, 1.2, 1.3])


def test_wrong_dtype_or_type_is_a_type_error():
    ex = laserlines.Extractor()
    with pytest.raises(TypeError, match=r"float64 or float32 \(metres\), got dtype int64"):
        ex.extract(np.arange(4), 0.0, 0.1)
    with pytest.raises(TypeError, match="numpy array of float64 or float32, got list"):
        ex.extract([1.0, 2.0], 0.0, 0.1)
    with pytest.raises(TypeError, match="needs angle_min and angle_increment"):
        ex.extract(GOOD)
    with pytest.raises(TypeError, match="angle_min must be a number, got str"):
        ex.extract(GOOD, "zero", 0.1)
    with pytest.raises(TypeError, match="range_max must be a number, got list"):
        laserlines.extract(GOOD, 0.0, 0.1, range_max=[5.6])


def test_wrong_shape_is_a_value_error():
    with pytest.raises(ValueError, match=r"1-D array, got shape \[2, 2\]"):
        laserlines.extract(np.ones((2, 2)), 0.0, 0.1)
    with pytest.raises(ValueError, match="1-D"):
        laserlines.extract(np.ones(()), 0.0, 0.1)


def test_broken_geometry_is_a_value_error():
    with pytest.raises(ValueError, match="angle_increment must be finite and non-zero, got 0"):
        laserlines.extract(GOOD, 0.0, 0.0)
    with pytest.raises(ValueError, match="angle_increment must be finite and non-zero, got NaN"):
        laserlines.extract(GOOD, 0.0, float("nan"))
    with pytest.raises(ValueError, match="angle_min must be finite"):
        laserlines.extract(GOOD, float("inf"), 0.1)
    with pytest.raises(ValueError, match="range limits must satisfy"):
        laserlines.extract(GOOD, 0.0, 0.1, range_min=2.0, range_max=1.0)
    with pytest.raises(ValueError, match="range limits"):
        laserlines.extract(GOOD, 0.0, 0.1, range_min=-1.0)
    with pytest.raises(ValueError, match="span more than a full turn"):
        laserlines.extract(np.ones(100), 0.0, 0.1)


def test_a_single_number_nan_limits_and_nan_poses_are_named():
    with pytest.raises(TypeError, match=r"got a single number \(float64\)"):
        laserlines.extract(np.float64(2.0), 0.0, 0.1)
    # range_max's default, inf, is shown as inf.
    with pytest.raises(ValueError, match="got range_min = NaN, range_max = inf"):
        laserlines.extract(GOOD, 0.0, 0.1, float("nan"))
    with pytest.raises(ValueError, match="stamp must be a finite number of seconds or None, got NaN"):
        laserlines.Scan(GOOD, 0.0, 0.1, stamp=float("nan"))
    with pytest.raises(ValueError, match=r"pose must be three finite numbers \(x, y, theta\)"):
        laserlines.Scan(GOOD, 0.0, 0.1, pose=(1.0, 2.0, float("nan")))
    with pytest.raises(ValueError, match="odometry must be three finite numbers"):
        laserlines.Scan(GOOD, 0.0, 0.1, odometry=(float("inf"), 2.0, 0.0))
    assert laserlines.Scan(GOOD, 0.0, 0.1, stamp=1.5, pose=(1.0, 2.0, 0.5)).stamp == 1.5


def test_a_pose_is_any_sequence_of_three_numbers():
    for given in ([1.0, 2.0, 0.5], np.array([1.0, 2.0, 0.5]), (1, 2, 0.5)):
        assert laserlines.Scan(GOOD, 0.0, 0.1, pose=given).pose == (1.0, 2.0, 0.5)
    with pytest.raises(ValueError, match="pose must be three finite numbers .* got 2 numbers"):
        laserlines.Scan(GOOD, 0.0, 0.1, pose=[1.0, 2.0])
    with pytest.raises(TypeError, match="odometry must be three finite numbers .* got str"):
        laserlines.Scan(GOOD, 0.0, 0.1, odometry="1 2 3")
    with pytest.raises(TypeError, match="pose must be three finite numbers .* got dict"):
        laserlines.Scan(GOOD, 0.0, 0.1, pose={"x": 1.0})


def test_a_path_is_str_bytes_or_path_like():
    expected = [len(s) for s in laserlines.read(str(EXCERPT))]
    assert len(expected) == 40
    assert [len(s) for s in laserlines.read(os.fsencode(EXCERPT))] == expected
    assert [len(s) for s in laserlines.read(EXCERPT)] == expected
    table = laserlines.extract_file(os.fsencode(EXCERPT))
    assert table.num_rows == laserlines.extract_file(str(EXCERPT)).num_rows > 0
    with pytest.raises(TypeError, match="path must be a str, bytes or os.PathLike, got int"):
        laserlines.read(3)


def test_signatures_show_inf_as_python_writes_it():
    assert "range_max=float('inf')" in laserlines.Scan.__text_signature__
    assert "range_max=float('inf')" in laserlines.Extractor.time_extract.__text_signature__


def test_unknown_or_invalid_parameters_are_named():
    with pytest.raises(ValueError, match="unknown field `ring_stp`, expected one of `ring_step`"):
        laserlines.Extractor(ring_stp=0.05)
    with pytest.raises(ValueError, match=r"\[iepf\] split_distance must be finite and >= 0, got -1"):
        laserlines.Extractor("iepf", split_distance=-1.0)
    with pytest.raises(ValueError, match="weight: unknown variant `square`"):
        laserlines.Extractor(weight="square")
    with pytest.raises(ValueError, match="criterion: invalid type: string"):
        laserlines.Extractor(criterion="high")
    with pytest.raises(ValueError, match='unknown noise "cheap"'):
        laserlines.Extractor(noise="cheap")
    with pytest.raises(ValueError, match='unknown algorithm "hough": expected one of hough-split'):
        laserlines.Extractor("hough")
    with pytest.raises(TypeError, match="parameter criterion: expected a bool, int, float, str"):
        laserlines.Extractor(criterion=None)
    with pytest.raises(ValueError, match="unknown field `ring_stp`"):
        laserlines.extract(GOOD, 0.0, 0.1, ring_stp=1.0)


def test_files_that_cannot_be_read_name_the_file_and_the_place(tmp_path):
    with pytest.raises(FileNotFoundError, match="no-such.dat: cannot open"):
        laserlines.read(tmp_path / "no-such.dat")
    bad = tmp_path / "bad.dat"
    bad.write_text("1 2 3\n")
    with pytest.raises(ValueError, match=r"bad.dat:1: expected 707 tokens"):
        list(laserlines.read(bad))
    it = laserlines.read(bad, skip_bad=True)
    assert list(it) == [] and it.skipped == 1
    with pytest.warns(UserWarning, match=r"bad.dat: skipped 1 bad record \(1 × malformed record\)"):
        assert laserlines.extract_file(bad, skip_bad=True).num_rows == 0
    with pytest.raises(ValueError, match="cannot tell the scan format"):
        laserlines.read(tmp_path / "scan.txt")
    with pytest.raises(ValueError, match="cannot read topic `/scan`"):
        laserlines.read(EXCERPT, topic="/scan")
    notparquet = tmp_path / "x.parquet"
    notparquet.write_bytes(b"PAR1 nothing PAR1")
    with pytest.raises(ValueError, match="x.parquet: byte 0: expected a Parquet file"):
        laserlines.extract_file(notparquet)


def test_bad_tables_name_the_column_and_the_row():
    pa = pytest.importorskip("pyarrow")
    ex = laserlines.Extractor()
    with pytest.raises(ValueError, match="column angle_min: expected a column of float64"):
        ex.extract_table(pa.table({"x": [1.0]}))
    t = pa.table(
        {
            "angle_min": [0.0, 0.0],
            "angle_increment": [0.1, 0.0],
            "range_min": [0.0, 0.0],
            "range_max": [5.0, 5.0],
            "ranges": [[1.0, 1.0], [1.0, 1.0]],
        }
    )
    with pytest.raises(ValueError, match="row 1: invalid scan: angle_increment"):
        ex.extract_table(t)
    numbered = pa.table(
        {
            "scan": pa.array([7, -3], pa.int64()),
            "angle_min": [0.0, 0.0],
            "angle_increment": [0.1, 0.1],
            "range_min": [0.0, 0.0],
            "range_max": [5.0, 5.0],
            "ranges": [[1.0, 1.0], [1.0, 1.0]],
        }
    )
    with pytest.raises(ValueError, match="row 1: column scan: expected an index of 0 or more, found -3"):
        ex.extract_table(numbered)
    with pytest.raises(TypeError, match="expected a table of scans: a pyarrow Table, .* got list"):
        ex.extract_table([1, 2, 3])
    with pytest.raises(TypeError, match="expected a table of LaserScan messages: .* got dict"):
        ex.extract_messages({"a": 1})


def test_a_scan_brings_its_own_range_limits():
    scan = next(iter(laserlines.read(EXCERPT)))
    with pytest.raises(TypeError, match="takes its range limits from the scan"):
        laserlines.extract(scan, range_min=4.0, range_max=4.5)
    with pytest.raises(TypeError, match="takes its range limits from the scan"):
        laserlines.Extractor().extract(scan, range_max=4.5)
    # The same limits on a scan of its own apply.
    limited = laserlines.Scan(scan.ranges, scan.angle_min, scan.angle_increment, 4.0, 4.5)
    assert len(laserlines.extract(limited)) < len(laserlines.extract(scan))


def test_empty_range_limits_and_runaway_grids_are_refused():
    for limits in ([2.0, 0.5], [float("nan"), 0.5], [-5.0, -1.0]):
        with pytest.raises(ValueError, match=r"range_limits\[[01]\]"):
            laserlines.Extractor(range_limits=limits)
    with pytest.raises(ValueError, match=r"range_limits\[1\] must be above"):
        laserlines.Extractor("ransac", range_limits=[3.0, 0.03])
    with pytest.raises(ValueError, match="ring_step must be finite and >= 0.0001"):
        laserlines.Extractor(ring_step=1e-8)
    with pytest.raises(ValueError, match=r"window must be at most"):
        laserlines.Extractor(window=1e6)


def test_numpy_values_and_big_ints_as_parameters():
    ex = laserlines.Extractor(min_line_points=np.int64(5), range_limits=np.array([0.1, 4.0]))
    assert ex.params["min_line_points"] == 5
    assert ex.params["range_limits"] == [0.1, 4.0]
    assert laserlines.Extractor("ransac", seed=np.uint32(7)).params["seed"] == 7
    with pytest.raises(TypeError, match=r"parameter seed: .*64-bit signed integers"):
        laserlines.Extractor("ransac", seed=2**64 - 1)


def test_masked_arrays_are_refused_and_other_endian_floats_read():
    masked = np.ma.masked_array(GOOD, mask=[False, True, False, False])
    with pytest.raises(TypeError, match=r"masked array.*numpy.ma.filled"):
        laserlines.extract(masked, 0.0, 0.1)
    scan = next(iter(laserlines.read(EXCERPT)))
    native = laserlines.extract(scan.ranges, scan.angle_min, scan.angle_increment)
    swapped = laserlines.extract(scan.ranges.astype(">f8"), scan.angle_min, scan.angle_increment)
    assert swapped.tobytes() == native.tobytes()


def test_time_extract_needs_a_repeat_of_one_or_more():
    for repeat in (0, -1):
        with pytest.raises(ValueError, match=f"repeat must be 1 to .*, got {repeat}"):
            laserlines.Extractor().time_extract(GOOD, 0.0, 0.1, repeat=repeat)


def test_a_format_reads_a_file_of_any_name(tmp_path):
    renamed = tmp_path / "scans.bin"
    renamed.write_bytes(EXCERPT.read_bytes())
    with pytest.raises(ValueError, match="scans.bin"):
        laserlines.read(renamed)
    with pytest.raises(ValueError, match=r'unknown format "nope": expected one of json, jsonl'):
        laserlines.read(renamed, format="nope")
    got = [s.stamp for s in laserlines.read(renamed, format="dat")]
    assert got == [s.stamp for s in laserlines.read(EXCERPT)]
    table = laserlines.extract_file(renamed, format="dat")
    assert table.equals(laserlines.extract_file(EXCERPT))


def test_help_tells_units_and_a_scan_prints_plainly():
    assert "REP 103" in laserlines.__doc__ and "covariance" in laserlines.__doc__
    scan = laserlines.Scan(GOOD, 0.0, 0.1, pose=(1.0, 2.0, 0.5))
    text = repr(scan)
    assert "Some(" not in text and "pose (1, 2, 0.5)" in text and "odometry None" in text
    assert scan.range_max == float("inf")


@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="needs /proc (Linux)")
def test_ctrl_c_ends_a_long_file(tmp_path):
    import json
    import signal

    # 20,000 scans of a 2 m wall and an alarm every 2 ms: the handler interrupts on its third
    # run and notes whether the file was still being read (open, its position short of its
    # end: the extraction checks for signals every 256 scans) rather than read to its end.
    angles = np.linspace(-0.5, 0.5, 100)
    scan = {
        "angle_min": -0.5,
        "angle_increment": float(angles[1] - angles[0]),
        "range_min": 0.02,
        "range_max": 5.6,
        "ranges": (2.0 / np.cos(angles)).round(4).tolist(),
    }
    path = tmp_path / "long.jsonl"
    path.write_text((json.dumps(scan) + "\n") * 20000)
    runs = []

    size = path.stat().st_size

    def still_reading():
        # The file open, its read position short of its end.
        for fd in os.listdir("/proc/self/fd"):
            try:
                if os.readlink(f"/proc/self/fd/{fd}") != str(path):
                    continue
                with open(f"/proc/self/fdinfo/{fd}") as info:
                    pos = int(info.readline().split()[1])
                return pos < size
            except OSError:
                pass
        return False

    def interrupt(signum, frame):
        runs.append(still_reading())
        if len(runs) == 3:
            raise KeyboardInterrupt

    previous = signal.signal(signal.SIGALRM, interrupt)
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.002, 0.002)
        with pytest.raises(KeyboardInterrupt):
            laserlines.extract_file(path)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    assert runs[2], "the interrupt came only after the whole file"
