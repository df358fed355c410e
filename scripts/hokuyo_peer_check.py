#!/usr/bin/env python3
"""Independent check of the Hokuyo emulator with hokuyolx (PyPI), a SCIP 2.0 client
nobody here wrote: it connects to `laserlines hokuyo-emulator --model ust-10lx` over TCP,
replaying the bundled URG-04LX excerpt (error codes included), runs its own start-up (time synchronisation with %ST/TM0/TM1/TM2, PP, BM), reads VV and
II, single scans (GD) and a stream (MD), and every scan it read must equal, value for
value and time stamp for time stamp, a scan the emulator logged as served.

Usage: hokuyo_peer_check.py --laserlines PATH [--scans N] [--timeout S]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import hokuyolx


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--laserlines", required=True)
    ap.add_argument("--scans", type=int, default=20)
    ap.add_argument("--log", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "..", "data", "urg04lx-exp1-excerpt.dat.gz"))
    ap.add_argument("--timeout", type=float, default=120.0)
    args = ap.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        served_path = os.path.join(tmp, "served.jsonl")
        emulator = subprocess.Popen(
            [args.laserlines, "hokuyo-emulator", "--model", "ust-10lx",
             "--tcp", "127.0.0.1:0", "--rate", "10", "--served", served_path,
             "--log", args.log,
             "--duration", str(args.timeout)],
            stdout=subprocess.PIPE, text=True)
        try:
            line = emulator.stdout.readline()
            if " on " not in line:
                raise SystemExit("emulator did not start: %r" % line)
            host, port = line.strip().rsplit(" on ", 1)[1].rsplit(":", 1)
            read = run_client(host, int(port), args.scans)
        finally:
            emulator.terminate()
            emulator.wait(timeout=30)
        served = {}
        with open(served_path) as f:
            for l in f:
                s = json.loads(l)
                served[(s["echo"][:2], s["timestamp"])] = s
    failures = 0
    for kind, ts, values in read:
        s = served.get((kind, ts))
        if s is None:
            print("FAIL: %s scan at %d ms was never served" % (kind, ts))
            failures += 1
        elif s["fault"] is not None or s["values"] != values:
            print("FAIL: %s scan at %d ms differs from the one served" % (kind, ts))
            failures += 1
    codes = sum(1 for _, _, v in read for x in v if x < 20)
    print("hokuyolx read %d scans (%d error codes among the readings); %d differ from the "
          "emulator's" % (len(read), codes, failures))
    if failures or len(read) < args.scans + 2 or codes == 0:
        print("0 passed, 1 failed")
        return 1
    print("1 passed, 0 failed")
    return 0


def run_client(host, port, scans):
    # Its own start-up: time sync (%ST, TM0, TM1 x10, TM2), PP, BM.
    laser = hokuyolx.HokuyoLX(addr=(host, port), convert_time=False, timeout=10)
    params = laser.sensor_parameters()
    version = laser.version()
    state = laser.sensor_state()
    assert params["AMAX"] == 1080 and params["ARES"] == 1440, params
    assert version["PROD"] == "SOKUIKI Sensor UST-10LX", version
    assert "LASR" in state, state
    print("hokuyolx start-up passed: model %s, t0 %d ms, laser state %s"
          % (laser.model, laser.tzero, laser.laser_state()[1]))
    read = []
    for _ in range(2):
        ts, scan = laser.get_dist()
        read.append(("GD", int(ts), [int(x) for x in scan]))
    for scan, ts, _pending in laser.iter_dist(scans=scans):
        read.append(("MD", int(ts), [int(x) for x in scan]))
    laser.standby()
    laser.close()
    return read


if __name__ == "__main__":
    sys.exit(main())
