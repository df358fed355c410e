"""The GIL is released while extracting: another Python thread runs during one long
extraction call. Checked by what runs, not by how fast: with the GIL held through the call
(one bytecode), no Python code of another thread could run while it lasts."""

import threading
import time

import numpy as np
import pytest

import laserlines
from conftest import EXCERPT

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")


def test_another_thread_runs_during_one_extraction_call(cli, tmp_path):
    cli("convert", EXCERPT, tmp_path / "scans.parquet")
    one = pq.read_table(tmp_path / "scans.parquet")
    # 300 copies of the 40 scans: one `extract_table` call of about 0.1-0.2 s.
    scans = pa.concat_tables([one] * 300)
    ex = laserlines.Extractor()
    beats = []
    stop = threading.Event()

    def beat():
        # Python code: it runs only while this thread holds the GIL.
        while not stop.is_set():
            beats.append(time.perf_counter())
            for _ in range(1000):
                pass

    t = threading.Thread(target=beat)
    t.start()
    try:
        while not beats:
            time.sleep(0.001)
        t0 = time.perf_counter()
        lines = ex.extract_table(scans)
        t1 = time.perf_counter()
    finally:
        stop.set()
        t.join()
    assert lines.num_rows > 12000
    # Beats in the middle 60 % of the call, away from its start and end (where the GIL may
    # change hands around the call itself).
    lo, hi = t0 + 0.2 * (t1 - t0), t1 - 0.2 * (t1 - t0)
    inside = sum(lo <= b <= hi for b in beats)
    assert inside >= 3, f"{inside} beats of the other thread during {t1 - t0:.3f} s of extraction"


def test_one_extractor_shared_by_threads_gives_the_same_lines():
    scans = list(laserlines.read(EXCERPT))
    ex = laserlines.Extractor()
    expected = [ex.extract(s)["r"] for s in scans]
    results = {}

    def run(k):
        results[k] = [ex.extract(s)["r"] for s in scans]

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in range(4):
        assert all(np.array_equal(a, b) for a, b in zip(results[k], expected))
