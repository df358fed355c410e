"""Bad input raises ValueError or TypeError with a clear message, never a crash."""

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
    with pytest.raises(TypeError):
        ex.extract(GOOD, "zero", 0.1)


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
    with pytest.warns(UserWarning, match=r"bad.dat: skipped 1 bad records \(1 malformed record\)"):
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
    with pytest.raises(TypeError):
        ex.extract_table([1, 2, 3])
