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


# A thread reads the extractor while another extracts a long file (which takes the GIL
# every 256 scans to look for Ctrl-C), and a signal handler extracts with the same
# extractor: each must wait its turn, never for ever. Run in a child process, so that a
# deadlock fails the test by its time limit instead of hanging the suite.
TAKE_TURNS = r"""
import json, signal, sys, threading, time
import numpy as np
import laserlines

path = sys.argv[1]
with open(path, "w") as f:
    inc = 0.01
    ranges = list(2.0 / np.cos(-0.5 + inc * np.arange(100)))
    row = json.dumps({"angle_min": -0.5, "angle_increment": inc, "range_min": 0.02,
                      "range_max": 30.0, "ranges": ranges})
    for _ in range(6000):
        f.write(row + "\n")
ex = laserlines.Extractor()
rows = []
worker = threading.Thread(target=lambda: rows.append(ex.extract_file(path).num_rows))
worker.start()
reads = 0
while worker.is_alive():
    ex.last_ranges_address
    reads += 1
worker.join()
assert rows == [6000], rows
# Ctrl-C's handler, run between scans of extract_file on this thread, extracts too.
handled = []
def handler(signum, frame):
    handled.append(len(ex.extract(np.array(ranges), -0.5, inc)))
signal.signal(signal.SIGINT, handler)
threading.Timer(0.05, lambda: signal.raise_signal(signal.SIGINT)).start()
t0 = time.perf_counter()
while not handled and time.perf_counter() - t0 < 20:
    ex.extract_file(path)
assert handled == [1], handled
print("took turns", reads)
"""


def test_readers_and_signal_handlers_take_turns_with_a_long_extraction(tmp_path):
    import subprocess
    import sys

    done = subprocess.run(
        [sys.executable, "-c", TAKE_TURNS, str(tmp_path / "long.jsonl")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("took turns"), done.stdout


def test_an_extractor_pickles_to_one_of_the_same_algorithm_and_parameters():
    import copy
    import pickle

    scans = list(laserlines.read(EXCERPT))[:5]
    for ex in [
        laserlines.Extractor(),
        laserlines.Extractor("iepf", split_distance=0.03, breakpoints={"noise": 0.02}),
        laserlines.Extractor(noise={"sigma_min": 0.01, "fraction": 0.01}, min_line_length=0.2),
    ]:
        for again in [pickle.loads(pickle.dumps(ex)), copy.deepcopy(ex), copy.copy(ex)]:
            assert again is not ex
            assert again.algorithm == ex.algorithm
            assert again.params == ex.params
            for s in scans:
                assert np.array_equal(again.extract(s), ex.extract(s))
