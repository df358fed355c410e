#!/usr/bin/env python3
"""Independent check of `laserlines-ros2` with another DDS: Eclipse Cyclone DDS (the Python
`cyclonedds` package, the DDS of several ROS 2 distributions).

    check       publishes the LaserScans of a real log on `rt/scan` with the ROS 2 wire names
                (`sensor_msgs::msg::dds_::LaserScan_`), once from a reliable and once from a
                best-effort writer, one node run each; subscribes to `rt/line_segments`,
                `rt/line_markers` (and `rt/line_sectors` with --sectors) and checks that every
                scan gets its line list with values equal to `laserlines extract` on the same
                scans (float32 in the message, float64 in the marker), then that a scan with
                angle_increment 0 gives a warning and no output, that NaN, inf and zero
                ranges are counted, that the node goes on, and that it exits cleanly on SIGINT.
    throughput  publishes URG-04LX scans at given rates and counts the line lists that come
                back: how many scans per second go through the node.

All traffic stays on this host: Cyclone DDS is configured (CYCLONEDDS_URI) to use the
loopback interface only, without multicast, with 127.0.0.1 as its discovery peer; the node
runs with --localhost-only. Each run uses its own DDS domain so that other DDS programs on
the machine do not interfere. Every wait is bounded.
"""

import argparse
import json
import math
import os
import signal
import struct
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, float32, float64, int32, sequence, uint8, uint32
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

# ---------------------------------------------------------------------------------------------
# The ROS 2 messages, from their .msg files (builtin_interfaces, std_msgs, sensor_msgs,
# geometry_msgs, visualization_msgs as of Humble; laser_line_extraction's LineSegment).


@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32
    nanosec: uint32


@dataclass
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time
    frame_id: str


@dataclass
class LaserScan(IdlStruct, typename="sensor_msgs::msg::dds_::LaserScan_"):
    header: Header
    angle_min: float32
    angle_max: float32
    angle_increment: float32
    time_increment: float32
    scan_time: float32
    range_min: float32
    range_max: float32
    ranges: sequence[float32]
    intensities: sequence[float32]


@dataclass
class LineSegment(IdlStruct, typename="laser_line_extraction::msg::dds_::LineSegment_"):
    radius: float32
    angle: float32
    covariance: array[float32, 4]
    start: array[float32, 2]
    end: array[float32, 2]


@dataclass
class LineSegmentList(IdlStruct, typename="laser_line_extraction::msg::dds_::LineSegmentList_"):
    header: Header
    line_segments: sequence[LineSegment]


@dataclass
class Point(IdlStruct, typename="geometry_msgs::msg::dds_::Point_"):
    x: float64
    y: float64
    z: float64


@dataclass
class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    x: float64
    y: float64
    z: float64
    w: float64


@dataclass
class Pose(IdlStruct, typename="geometry_msgs::msg::dds_::Pose_"):
    position: Point
    orientation: Quaternion


@dataclass
class Vector3(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
    x: float64
    y: float64
    z: float64


@dataclass
class ColorRGBA(IdlStruct, typename="std_msgs::msg::dds_::ColorRGBA_"):
    r: float32
    g: float32
    b: float32
    a: float32


@dataclass
class Duration(IdlStruct, typename="builtin_interfaces::msg::dds_::Duration_"):
    sec: int32
    nanosec: uint32


@dataclass
class CompressedImage(IdlStruct, typename="sensor_msgs::msg::dds_::CompressedImage_"):
    header: Header
    format: str
    data: sequence[uint8]


@dataclass
class UVCoordinate(IdlStruct, typename="visualization_msgs::msg::dds_::UVCoordinate_"):
    u: float32
    v: float32


@dataclass
class MeshFile(IdlStruct, typename="visualization_msgs::msg::dds_::MeshFile_"):
    filename: str
    data: sequence[uint8]


@dataclass
class Marker(IdlStruct, typename="visualization_msgs::msg::dds_::Marker_"):
    header: Header
    ns: str
    id: int32
    type: int32
    action: int32
    pose: Pose
    scale: Vector3
    color: ColorRGBA
    lifetime: Duration
    frame_locked: bool
    points: sequence[Point]
    colors: sequence[ColorRGBA]
    texture_resource: str
    texture: CompressedImage
    uv_coordinates: sequence[UVCoordinate]
    text: str
    mesh_resource: str
    mesh_file: MeshFile
    mesh_use_embedded_materials: bool


@dataclass
class MarkerArray(IdlStruct, typename="visualization_msgs::msg::dds_::MarkerArray_"):
    markers: sequence[Marker]


LINE_LIST = 5
DELETE = 2

# ---------------------------------------------------------------------------------------------
# Cyclone DDS on loopback only.

CYCLONE_LOOPBACK = """<CycloneDDS><Domain id="any">
  <General>
    <Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>
    <AllowMulticast>false</AllowMulticast>
  </General>
  <Discovery>
    <ParticipantIndex>auto</ParticipantIndex>
    <MaxAutoParticipantIndex>20</MaxAutoParticipantIndex>
    <Peers><Peer address="127.0.0.1"/></Peers>
  </Discovery>
</Domain></CycloneDDS>"""


def f32(x):
    """x rounded to float32, as a Python float."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def fail(msg):
    print(f"ros2_peer_check: FAILED: {msg}", file=sys.stderr)
    sys.exit(1)


def reader_qos(depth=1000):
    return Qos(
        Policy.Reliability.Reliable(duration(seconds=1)),
        Policy.History.KeepLast(depth),
        Policy.DataRepresentation(use_cdrv0_representation=True),
    )


def writer_qos(reliable, depth=1000):
    rel = (
        Policy.Reliability.Reliable(duration(seconds=1))
        if reliable
        else Policy.Reliability.BestEffort
    )
    return Qos(
        rel,
        Policy.History.KeepLast(depth),
        Policy.DataRepresentation(use_cdrv0_representation=True),
    )


class Peer:
    """A Cyclone DDS participant with the node's topics."""

    def __init__(self, domain, reliable, sectors):
        self.dp = DomainParticipant(domain)
        scan_topic = Topic(self.dp, "rt/scan", LaserScan)
        self.writer = DataWriter(self.dp, scan_topic, qos=writer_qos(reliable))
        self.lines = DataReader(self.dp, Topic(self.dp, "rt/line_segments", LineSegmentList), qos=reader_qos())
        self.markers = DataReader(self.dp, Topic(self.dp, "rt/line_markers", Marker), qos=reader_qos())
        self.sectors = (
            DataReader(self.dp, Topic(self.dp, "rt/line_sectors", MarkerArray), qos=reader_qos())
            if sectors
            else None
        )

    def readers(self):
        return [r for r in (self.lines, self.markers, self.sectors) if r is not None]

    def wait_matched(self, timeout_s):
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            if self.writer.get_matched_subscriptions() and all(
                r.get_matched_publications() for r in self.readers()
            ):
                return True
            time.sleep(0.05)
        return False


def start_node(node_bin, domain, extra, log_path):
    env = dict(os.environ)
    env.pop("RUST_LOG", None)
    log = open(log_path, "w")
    cmd = [node_bin, "--localhost-only", "--domain-id", str(domain), "--status-every", "0", *extra]
    return subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env), log


def stop_node(proc, log, timeout_s=10):
    proc.send_signal(signal.SIGINT)
    try:
        code = proc.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        fail(f"the node did not exit within {timeout_s} s of SIGINT")
    log.close()
    return code


# ---------------------------------------------------------------------------------------------
# Scans: the log as laserlines reads it, rounded to what a LaserScan message carries.


def load_scans(laserlines, log, work):
    """The log's scans as float32 LaserScan fields, and the same scans as JSONL for
    `laserlines extract` (float32 values written as float64)."""
    raw = os.path.join(work, "scans.jsonl")
    subprocess.run([laserlines, "convert", log, raw], check=True, capture_output=True)
    scans = []
    with open(raw) as f:
        for k, line in enumerate(f):
            s = json.loads(line)
            ranges = [math.inf if r is None else f32(r) for r in s["ranges"]]
            scans.append(
                {
                    "angle_min": f32(s["angle_min"]),
                    "angle_increment": f32(s["angle_increment"]),
                    "range_min": f32(s["range_min"]),
                    "range_max": f32(s["range_max"]),
                    "ranges": ranges,
                    # Stamps one second apart from 1000 s: each list names its scan.
                    "sec": 1000 + k,
                    "nanosec": 250_000_000,
                }
            )
    return scans


def write_jsonl(scans, path):
    with open(path, "w") as f:
        for s in scans:
            obj = {
                "angle_min": s["angle_min"],
                "angle_increment": s["angle_increment"],
                "range_min": s["range_min"],
                "range_max": s["range_max"],
                "ranges": [None if not math.isfinite(r) else r for r in s["ranges"]],
                "stamp": s["sec"] + s["nanosec"] * 1e-9,
            }
            f.write(json.dumps(obj) + "\n")


def to_msg(s, frame_id="laser"):
    n = len(s["ranges"])
    return LaserScan(
        header=Header(stamp=Time(sec=s["sec"], nanosec=s["nanosec"]), frame_id=frame_id),
        angle_min=s["angle_min"],
        angle_max=f32(s["angle_min"] + (n - 1) * s["angle_increment"]),
        angle_increment=s["angle_increment"],
        time_increment=0.0,
        scan_time=0.1,
        range_min=s["range_min"],
        range_max=s["range_max"],
        ranges=s["ranges"],
        intensities=[],
    )


def expected_lines(laserlines, scans, work, algorithm):
    path = os.path.join(work, "published.jsonl")
    write_jsonl(scans, path)
    out = os.path.join(work, "expected.jsonl")
    subprocess.run(
        [laserlines, "extract", path, "-o", out, "--algorithm", algorithm],
        check=True,
        capture_output=True,
    )
    with open(out) as f:
        return [json.loads(line)["lines"] for line in f]


# ---------------------------------------------------------------------------------------------
# Comparisons.


def compare_list(k, msg, want, frame_id):
    if (msg.header.stamp.sec, msg.header.stamp.nanosec) != (1000 + k, 250_000_000):
        fail(f"scan {k}: header stamp {msg.header.stamp} is not the scan's")
    if msg.header.frame_id != frame_id:
        fail(f"scan {k}: frame_id {msg.header.frame_id!r}, expected {frame_id!r}")
    got = msg.line_segments
    if len(got) != len(want):
        fail(f"scan {k}: {len(got)} line segments, laserlines extract gives {len(want)}")
    for j, (g, w) in enumerate(zip(got, want)):
        cov = w["covariance"]
        expect = {
            "radius": [f32(w["r"])],
            "angle": [f32(w["alpha"])],
            "covariance": [f32(cov[0][0]), f32(cov[0][1]), f32(cov[1][0]), f32(cov[1][1])],
            "start": [f32(v) for v in w["start"]],
            "end": [f32(v) for v in w["end"]],
        }
        values = {
            "radius": [g.radius],
            "angle": [g.angle],
            "covariance": list(g.covariance),
            "start": list(g.start),
            "end": list(g.end),
        }
        for name, e in expect.items():
            if values[name] != e:
                fail(f"scan {k} line {j}: {name} {values[name]} != {e} (laserlines extract)")


def compare_marker(k, m, want, frame_id):
    if m.header.frame_id != frame_id or m.type != LINE_LIST or m.ns != "line_extraction":
        fail(f"scan {k}: marker {m.ns!r}/{m.type} in {m.header.frame_id!r}")
    expect = []
    for w in want:
        expect += [(w["start"][0], w["start"][1], 0.0), (w["end"][0], w["end"][1], 0.0)]
    got = [(p.x, p.y, p.z) for p in m.points]
    if got != expect:
        fail(f"scan {k}: marker points differ from laserlines extract's end points")


def check_sectors(k, arr, want):
    """Each sector object must be a piece of one of the scan's lines, within its sector."""
    bounds = {0: (50.0, 120.0), 1: (-50.0, 50.0), 2: (-120.0, -50.0)}
    objects = [m for m in arr.markers if m.ns == "sector_objects"]
    if sorted(m.id for m in objects) != [0, 1, 2]:
        fail(f"scan {k}: sector objects {[m.id for m in objects]}")
    for m in objects:
        if m.action == DELETE:
            continue
        lo, hi = bounds[m.id]
        for p in m.points:
            bearing = math.degrees(math.atan2(p.y, p.x))
            if not (lo - 1e-6 <= bearing <= hi + 1e-6):
                fail(f"scan {k}: sector {m.id} point at {bearing:.3f} deg, outside {lo}..{hi}")
            on_line = any(
                abs(p.x * math.cos(w["alpha"]) + p.y * math.sin(w["alpha"]) - w["r"]) < 1e-6
                for w in want
            )
            if not on_line:
                fail(f"scan {k}: sector {m.id} point ({p.x}, {p.y}) on none of the scan's lines")


def take_all(reader, into):
    for s in reader.take(N=1000):
        into.append(s)


def wait_for(cond, timeout_s):
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        if cond():
            return True
        time.sleep(0.002)
    return False


# ---------------------------------------------------------------------------------------------
# The round trip.


def round_trip(args, scans, want, reliable, domain, work):
    mode = "reliable" if reliable else "best-effort"
    frame_id = "laser"
    extra = ["--algorithm", args.algorithm]
    if args.sectors:
        extra.append("--sectors")
    log_path = os.path.join(work, f"node-{mode}.log")
    node, log = start_node(args.node, domain, extra, log_path)
    peer = Peer(domain, reliable, args.sectors)
    try:
        if not peer.wait_matched(args.discovery_timeout):
            fail(f"{mode}: the node and Cyclone DDS did not match within {args.discovery_timeout} s")
        lists, markers, sectors = [], [], []

        def got(n):
            take_all(peer.lines, lists)
            take_all(peer.markers, markers)
            if peer.sectors is not None:
                take_all(peer.sectors, sectors)
            return len(lists) >= n and len(markers) >= n and (peer.sectors is None or len(sectors) >= n)

        # One scan at a time: each must come back before the next is sent.
        for k, s in enumerate(scans):
            peer.writer.write(to_msg(s, frame_id))
            if not wait_for(lambda: got(k + 1), args.scan_timeout):
                fail(f"{mode}: no line list for scan {k} within {args.scan_timeout} s")
        for k in range(len(scans)):
            compare_list(k, lists[k], want[k], frame_id)
            compare_marker(k, markers[k], want[k], frame_id)
            if peer.sectors is not None:
                check_sectors(k, sectors[k], want[k])

        # Bad scans: angle_increment 0 gives no output; NaN, inf and zero ranges are counted
        # and the scan goes through; the node goes on.
        bad = dict(scans[0], angle_increment=0.0, sec=5000)
        peer.writer.write(to_msg(bad, frame_id))
        holes = dict(scans[1], sec=5001)
        holes["ranges"] = list(holes["ranges"])
        holes["ranges"][0:3] = [math.nan, math.inf, 0.0]
        peer.writer.write(to_msg(holes, frame_id))
        n = len(scans)
        if not wait_for(lambda: got(n + 1), args.scan_timeout):
            fail(f"{mode}: no line list after the bad scans")
        stamps = [m.header.stamp.sec for m in lists[n:]]
        if stamps != [5001]:
            fail(f"{mode}: after the bad scans, lists for stamps {stamps}, expected [5001] only")
        peer.writer.write(to_msg(scans[2], frame_id))
        if not wait_for(lambda: got(n + 2), args.scan_timeout):
            fail(f"{mode}: the node did not go on after the bad scans")
        compare_list(2, lists[n + 1], want[2], frame_id)
    finally:
        code = stop_node(node, log)
    with open(log_path) as f:
        text = f.read()
    if code != 0:
        fail(f"{mode}: the node exited with {code} on SIGINT:\n{text}")
    total = len(scans) + 3
    extracted = scans + [holes, scans[2]]
    counts = {"NaN": 0, "inf": 0, "zero": 0, "negative": 0}
    for s in extracted:
        for r in s["ranges"]:
            kind = "NaN" if math.isnan(r) else "inf" if math.isinf(r) else "zero" if r == 0 else "negative" if r < 0 else None
            if kind:
                counts[kind] += 1
    with_bad = sum(1 for s in extracted if any(not (math.isfinite(r) and r > 0) for r in s["ranges"]))
    needs = [
        "angle_increment must be finite and non-zero, got 0 (1 skipped so far)",
        "ranges are no measurement (",
        f"scans seen {total}, extracted {total - 1}, skipped 1 (1 bad geometry, 0 undecodable)",
        f"ranges not used ({with_bad} scans): {counts['NaN']} NaN, {counts['inf']} inf, "
        f"{counts['zero']} zero, {counts['negative']} negative; outputs not published 0",
        "stopping (signal)",
    ]
    for s in needs:
        if s not in text:
            fail(f"{mode}: the node's log lacks {s!r}:\n{text}")
    if "panicked" in text:
        fail(f"{mode}: the node panicked:\n{text}")
    lines = sum(len(w) for w in want)
    print(
        f"ros2_peer_check: {mode} publisher: {len(scans)} scans, {lines} lines equal to "
        f"laserlines extract (float32 list, float64 marker{', sector objects on their lines' if args.sectors else ''}); "
        f"angle_increment 0 skipped with a warning, NaN/inf/zero ranges counted; clean exit on SIGINT"
    )


def check(args):
    work = tempfile.mkdtemp(prefix="ros2-peer-")
    scans = load_scans(args.laserlines, args.log, work)
    want = expected_lines(args.laserlines, scans, work, args.algorithm)
    if len(want) != len(scans):
        fail(f"laserlines extract gave {len(want)} scans for {len(scans)}")
    if sum(len(w) for w in want) == 0:
        fail("no lines at all: nothing would be compared")
    base = args.domain
    round_trip(args, scans, want, True, base, work)
    round_trip(args, scans, want, False, base + 1, work)
    print("ros2_peer_check: 2 passed, 0 failed")


# ---------------------------------------------------------------------------------------------
# Throughput.


def throughput(args):
    work = tempfile.mkdtemp(prefix="ros2-rate-")
    scans = load_scans(args.laserlines, args.log, work)
    msgs = [to_msg(s) for s in scans]
    beams = len(scans[0]["ranges"])
    log_path = os.path.join(work, "node.log")
    node, log = start_node(args.node, args.domain, ["--algorithm", args.algorithm, "--scan-depth", str(args.scan_depth)], log_path)
    peer = Peer(args.domain, True, False)
    try:
        if not peer.wait_matched(args.discovery_timeout):
            fail("the node and Cyclone DDS did not match")
        print(f"| rate asked [scans/s] | scans sent | send rate [scans/s] | lists received | lost | received [scans/s] |")
        print("|---:|---:|---:|---:|---:|---:|")
        for rate in args.rates:
            n = int(rate * args.seconds)
            lists = []
            take_all(peer.lines, lists)
            lists.clear()
            period = 1.0 / rate
            t0 = time.monotonic()
            for i in range(n):
                m = msgs[i % len(msgs)]
                m.header.stamp = Time(sec=i, nanosec=0)
                peer.writer.write(m)
                if i % 64 == 0:
                    take_all(peer.lines, lists)
                ahead = t0 + (i + 1) * period - time.monotonic()
                if ahead > 0:
                    time.sleep(ahead)
            t_sent = time.monotonic() - t0
            wait_for(lambda: (take_all(peer.lines, lists), len(lists) >= n)[1], 2.0)
            take_all(peer.lines, lists)
            received = len({m.header.stamp.sec for m in lists})
            print(
                f"| {rate:.0f} | {n} | {n / t_sent:.0f} | {received} | {n - received} | "
                f"{received / t_sent:.0f} |"
            )
            time.sleep(0.5)
    finally:
        code = stop_node(node, log)
    if code != 0:
        fail(f"the node exited with {code}")
    with open(log_path) as f:
        status = [l for l in f if "scans seen" in l]
    if status:
        print("node: " + status[-1].split("laserlines_ros2: ")[-1].strip())
    print(f"({beams} beams per scan, {args.algorithm}, reliable Cyclone DDS writer, best-effort node subscription of depth {args.scan_depth}, loopback)")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("mode", choices=["check", "throughput"])
    p.add_argument("--laserlines", required=True, help="the laserlines binary")
    p.add_argument("--node", required=True, help="the laserlines-ros2 binary")
    p.add_argument("--log", default="data/urg04lx-exp1-excerpt.dat.gz", help="scans to publish")
    p.add_argument("--algorithm", default="hough-split")
    p.add_argument("--sectors", action="store_true", help="also check the sector objects")
    p.add_argument("--domain", type=int, default=100 + os.getpid() % 100, help="DDS domain")
    p.add_argument("--discovery-timeout", type=float, default=30.0)
    p.add_argument("--scan-timeout", type=float, default=5.0)
    p.add_argument("--rates", type=float, nargs="+", default=[500, 1000, 2000, 4000])
    p.add_argument("--seconds", type=float, default=3.0, help="seconds per rate")
    p.add_argument("--scan-depth", type=int, default=5)
    args = p.parse_args()
    os.environ["CYCLONEDDS_URI"] = CYCLONE_LOOPBACK
    if args.mode == "check":
        check(args)
    else:
        throughput(args)


if __name__ == "__main__":
    main()
