"""What a call from Python costs beyond the Rust extraction it runs, per scan.

    python crates/laserlines-py/bench/overhead.py [--algorithm hough-split] [--repeat 2000]

For each scan of the bundled URG-04LX excerpt (682 beams): the time of
`Extractor.extract(ranges, ...)` measured with timeit (best of 5 rounds of `repeat` calls),
minus the time of the same extraction measured in Rust alone (`Extractor.time_extract`, the
same scan, the same number of calls, best of 5). Prints the median over the scans of both
times and of their difference: the binding's overhead (argument parsing, the numpy borrow,
releasing and taking back the GIL, the structured array of lines).
"""

import argparse
import pathlib
import statistics
import timeit

import laserlines

EXCERPT = pathlib.Path(__file__).resolve().parents[3] / "data" / "urg04lx-exp1-excerpt.dat.gz"


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--algorithm", default="hough-split")
    p.add_argument("--repeat", type=int, default=2000)
    args = p.parse_args()
    ex = laserlines.Extractor(args.algorithm)
    python, native, overhead, lines = [], [], [], []
    for s in laserlines.read(EXCERPT):
        geometry = (s.angle_min, s.angle_increment, s.range_min, s.range_max)
        call = lambda: ex.extract(s.ranges, *geometry)  # noqa: E731
        lines.append(len(call()["r"]))
        t_py = min(timeit.repeat(call, number=args.repeat, repeat=5)) / args.repeat
        t_rs = min(ex.time_extract(s.ranges, *geometry, repeat=args.repeat) for _ in range(5))
        python.append(t_py)
        native.append(t_rs)
        overhead.append(t_py - t_rs)
    # A scan without a valid range: the extraction does next to nothing, so the call is
    # almost all binding.
    import numpy as np

    empty = np.full(682, np.nan)
    geometry = (s.angle_min, s.angle_increment, s.range_min, s.range_max)
    t_py = min(timeit.repeat(lambda: ex.extract(empty, *geometry), number=args.repeat, repeat=9))
    t_rs = min(ex.time_extract(empty, *geometry, repeat=args.repeat) for _ in range(9))
    us = 1e6
    print(f"a scan of 682 beams without a valid range: from Python {t_py / args.repeat * us:.2f} us, "
          f"in Rust {t_rs * us:.2f} us, overhead {(t_py / args.repeat - t_rs) * us:.2f} us")
    print(f"{args.algorithm}, {len(python)} scans of the URG-04LX excerpt, {statistics.mean(lines):.1f} lines per scan")
    print(f"Extractor.extract from Python: median {statistics.median(python) * us:.2f} us per scan")
    print(f"the Rust extraction alone:      median {statistics.median(native) * us:.2f} us per scan")
    print(f"overhead of the binding:        median {statistics.median(overhead) * us:.2f} us per scan "
          f"(min {min(overhead) * us:.2f}, max {max(overhead) * us:.2f})")


if __name__ == "__main__":
    main()
