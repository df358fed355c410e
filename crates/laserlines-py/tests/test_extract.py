"""Values: the bindings give what the Rust extractor gives (the `laserlines` command), bit
for bit, for every algorithm; a contiguous float64 array is read in place."""

import json
import math

import numpy as np
import pytest

import laserlines
from conftest import EXCERPT, REPO, same_lines


def scans():
    return list(laserlines.read(EXCERPT))


def test_read_gives_every_scan_with_stamp_and_pose():
    s = scans()
    assert len(s) == 40
    assert len(s[0]) == 682 and s[0].ranges.dtype == np.float64
    assert s[0].stamp == 212.387282
    assert s[0].pose is not None and len(s[0].pose) == 3
    assert s[0].angle_increment == pytest.approx(np.radians(360 / 1024))


def test_lines_equal_the_cli_bit_for_bit(excerpt_lines):
    ex = laserlines.Extractor()
    total = 0
    for scan, expected in zip(scans(), excerpt_lines):
        lines = ex.extract(
            scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max
        )
        same_lines(lines, expected["lines"])
        same_lines(ex.extract(scan), expected["lines"])
        total += len(lines["r"])
    assert total > 100
    # The module-level function, with a fresh extractor.
    s = scans()[7]
    same_lines(
        laserlines.extract(s.ranges, s.angle_min, s.angle_increment, s.range_min, s.range_max),
        excerpt_lines[7]["lines"],
    )


def test_the_lines_have_documented_fields_shapes_and_types():
    s = scans()[3]
    lines = laserlines.Extractor().extract(s)
    n = len(lines)
    assert n > 0 and lines.shape == (n,)
    assert lines.dtype.names == (
        "start", "end", "r", "alpha", "first", "last", "points", "rms", "covariance"
    )
    assert lines["start"].shape == (n, 2) and lines["end"].shape == (n, 2)
    assert lines["covariance"].shape == (n, 2, 2)
    assert lines["first"].dtype == np.int64 and lines["r"].dtype == np.float64
    assert np.all(lines["first"] <= lines["last"])
    # The covariance is symmetric.
    assert np.array_equal(lines["covariance"][:, 0, 1], lines["covariance"][:, 1, 0])


@pytest.mark.parametrize("algorithm", laserlines.ALGORITHMS)
def test_every_algorithm_by_name_equals_the_cli(algorithm, cli, tmp_path):
    out = tmp_path / "lines.jsonl"
    cli("extract", EXCERPT, "-o", out, "--algorithm", algorithm)
    expected = [json.loads(line) for line in out.read_text().splitlines()]
    ex = laserlines.Extractor(algorithm)
    assert ex.algorithm == algorithm
    for scan, e in zip(scans(), expected):
        same_lines(ex.extract(scan), e["lines"])


def test_parameters_lay_over_the_defaults_like_a_params_file(cli, tmp_path):
    params = tmp_path / "p.toml"
    params.write_text(
        '[hough-split]\nsplit_sigmas = 6.0\nmin_line_length = 0.3\nnoise = "urg-04lx"\n'
    )
    out = tmp_path / "lines.jsonl"
    cli("extract", EXCERPT, "-o", out, "--params", params)
    expected = [json.loads(line) for line in out.read_text().splitlines()]
    ex = laserlines.Extractor(split_sigmas=6.0, min_line_length=0.3, noise="urg-04lx")
    assert ex.params["min_line_length"] == 0.3
    assert ex.params["criterion"] == laserlines.Extractor().params["criterion"]
    for scan, e in zip(scans(), expected):
        same_lines(ex.extract(scan), e["lines"])
    # Nested parameters as dicts, presets by name.
    iepf = laserlines.Extractor("iepf", breakpoints={"noise": 0.02})
    assert iepf.params["breakpoints"]["noise"] == 0.02
    assert laserlines.Extractor(paper=True).params["range_limits"] == [0.03, 3.0]
    defaults = laserlines.Extractor().params
    assert (defaults["max_r_sd"], defaults["max_alpha_sd"]) == (0.06, math.radians(3.0))
    assert defaults["min_advance_t"] == 8.0
    assert laserlines.Extractor(paper=True).params["min_advance_t"] == 0.0
    assert defaults["arc_significance"] == 2.0
    assert laserlines.Extractor(paper=True).params["arc_significance"] == 0.0
    complete = laserlines.Extractor(complete=True).params
    assert (complete["max_r_sd"], complete["max_alpha_sd"]) == (math.inf, math.radians(5.0))
    noise = laserlines.Extractor(noise={"sigma_min": 0.004, "fraction": 0.002})
    assert noise.params["noise"] == {"sigma_min": 0.004, "fraction": 0.002}


def test_a_contiguous_float64_array_is_read_in_place():
    s = scans()[5]
    ex = laserlines.Extractor()
    a = np.ascontiguousarray(s.ranges)
    expected = ex.extract(a, s.angle_min, s.angle_increment, s.range_min, s.range_max)
    assert ex.last_ranges_address == a.ctypes.data
    # A scan's own array too.
    ex.extract(s)
    assert ex.last_ranges_address == s.ranges.ctypes.data
    # float32 and strided arrays are converted: another buffer, the values of the conversion.
    f32 = a.astype(np.float32)
    lines32 = ex.extract(f32, s.angle_min, s.angle_increment, s.range_min, s.range_max)
    assert ex.last_ranges_address != f32.ctypes.data
    widened = f32.astype(np.float64)
    same = ex.extract(widened, s.angle_min, s.angle_increment, s.range_min, s.range_max)
    assert np.array_equal(lines32["r"], same["r"])
    wide = np.empty(2 * len(a))
    wide[::2] = a
    strided = wide[::2]
    lines = ex.extract(strided, s.angle_min, s.angle_increment, s.range_min, s.range_max)
    assert ex.last_ranges_address not in (wide.ctypes.data, strided.ctypes.data)
    assert np.array_equal(lines["r"], expected["r"])
    # The array is not changed.
    assert np.array_equal(a, s.ranges)


def test_a_clockwise_scan_gives_the_same_lines():
    s = scans()[10]
    ex = laserlines.Extractor(noise="urg-04lx")
    forward = ex.extract(s)
    angle_max = s.angle_min + (len(s) - 1) * s.angle_increment
    backward = ex.extract(
        s.ranges[::-1].copy(), angle_max, -s.angle_increment, s.range_min, s.range_max
    )
    assert len(backward["r"]) == len(forward["r"])
    np.testing.assert_allclose(np.sort(backward["r"]), np.sort(forward["r"]), atol=1e-6)
    n = len(s) - 1
    assert sorted(n - backward["last"]) == sorted(forward["first"])


def test_no_range_limit_by_default():
    inc = np.radians(0.5)
    angles = np.radians(-45) + inc * np.arange(181)
    ranges = 2.0 / np.cos(angles)  # a wall at x = 2 m
    lines = laserlines.extract(ranges, np.radians(-45), inc)
    assert len(lines["r"]) == 1
    assert lines["r"][0] == pytest.approx(2.0, abs=1e-9)
    assert lines["alpha"][0] == pytest.approx(0.0, abs=1e-9)
    assert (lines["first"][0], lines["last"][0]) == (0, 180)


def test_a_scan_keeps_its_pose_and_odometry():
    s = laserlines.Scan(
        np.full(10, 2.0), 0.0, 0.01, pose=(1.0, 2.0, 0.5), odometry=(3.0, 4.0, -0.5)
    )
    assert s.pose == (1.0, 2.0, 0.5) and s.odometry == (3.0, 4.0, -0.5)
    bare = laserlines.Scan(np.ones(3), 0.0, 0.1)
    assert bare.pose is None and bare.odometry is None


def leg_before_wall():
    """A URG-04LX scan (682 beams of 360/1024 deg) of a wall at x = 3 m, y from -3 to 3 m,
    with a 5 cm leg whose front stands 0.25 m before it, straight ahead; no noise, ranges
    rounded to the millimetre."""
    inc = math.radians(360 / 1024)
    angles = -340 * inc + inc * np.arange(682)
    ranges = np.full(682, np.nan)
    wall = 3.0 / np.cos(angles)
    ranges[np.abs(wall * np.sin(angles)) <= 3.0] = wall[np.abs(wall * np.sin(angles)) <= 3.0]
    cx, radius = 2.75, 0.025
    along = cx * np.cos(angles)
    h2 = radius**2 - (cx**2 - along**2)
    leg = h2 >= 0
    ranges[leg] = along[leg] - np.sqrt(h2[leg])
    return np.round(ranges, 3), -340 * inc, inc


def test_cut_excursions_is_a_keyword_and_keeps_the_wall_behind_a_leg():
    ranges, angle_min, inc = leg_before_wall()
    # With the cut (the default), the wall on both sides of the leg; without it, the leg's
    # points spoil the wall's only piece and no line is left.
    lines = laserlines.Extractor().extract(ranges, angle_min, inc, 0.02, 5.6)
    assert len(lines) == 2
    assert np.allclose(lines["r"], 3.0, atol=0.005)
    assert lines["last"][0] < 341 < lines["first"][1]
    off = laserlines.Extractor(cut_excursions=False).extract(ranges, angle_min, inc, 0.02, 5.6)
    assert len(off) == 0


def test_readings_at_their_own_bearings_grid_as_the_csv_reader_does():
    # The fixture of a spinning scanner's raw readings: clockwise degrees and millimetres.
    path = REPO / "crates" / "laserlines-io" / "tests" / "fixtures" / "readings_room.csv"
    rows = [line.split(",") for line in path.read_text().splitlines()
            if line and not line.startswith("#") and not line.startswith("angle")]
    bearings = -np.radians([float(a) for a, _ in rows])
    ranges = np.array([float(r) for _, r in rows]) * 1e-3  # as the reader converts
    scan, shared = laserlines.scan_from_bearings(bearings, ranges, range_min=0.15, range_max=12.0)
    assert shared == 38
    it = laserlines.read(path)
    (read,) = list(it)
    assert it.skip_reasons == {
        "reading on a beam that kept a better one (readings put on a grid of beams)": 38
    }
    assert scan.angle_min == read.angle_min and scan.angle_increment == read.angle_increment
    assert np.array_equal(scan.ranges, read.ranges, equal_nan=True)
    lines = laserlines.Extractor().extract(scan)
    # The room x = +-2, y = +-1.5 m seen from (0.5, -0.3): its four walls.
    for r, alpha in [(1.5, 0.0), (2.5, np.pi), (1.8, np.pi / 2), (1.2, -np.pi / 2)]:
        d_alpha = np.abs((lines["alpha"] - alpha + np.pi) % (2 * np.pi) - np.pi)
        assert np.any((np.abs(lines["r"] - r) < 0.03) & (d_alpha < 0.03)), (r, alpha, lines)
    with pytest.raises(ValueError, match="3 bearings but 2 ranges"):
        laserlines.scan_from_bearings([0.0, 0.1, 0.2], [1.0, 1.0])
    with pytest.raises(ValueError, match="bearing 1 must be finite"):
        laserlines.scan_from_bearings([0.0, float("nan")], [1.0, 1.0])
