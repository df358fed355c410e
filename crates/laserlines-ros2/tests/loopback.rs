//! The node over DDS on loopback, with a second participant of this process as the robot:
//! the bundled URG-04LX scans published from a reliable and from a best-effort writer each
//! come back as the line list and marker the processor makes of them, with the scan's
//! header; a scan with `angle_increment` 0 gives nothing and the node goes on; the node
//! stops when told. (The independent check with Cyclone DDS is `scripts/ros2_peer_check.py`.)

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::net::{IpAddr, Ipv4Addr};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread;
use std::time::{Duration, Instant};

use laserlines_ros2::msg::{self, Header, LaserScan, LineSegmentList, Marker, Time};
use laserlines_ros2::node::{Limits, LineNode, NodeConfig, output_qos};
use laserlines_ros2::process::{Outputs, Processor};
use ros2_client::dds::rustdds::DomainParticipantBuilder;
use ros2_client::qos::{History, Reliability, WhenFull};
use ros2_client::{
    Context, Name, Node, NodeName, NodeOptions, Publisher, QosProfile, Subscription,
};

fn processor() -> Processor {
    let ex = laserlines::registry::build("hough-split").unwrap().unwrap();
    Processor::new(ex, None, false)
}

/// The bundled excerpt as LaserScan messages (float32), stamped 100 s + k.
fn scans() -> Vec<LaserScan> {
    laserlines_io::demo::urg04lx_excerpt()
        .unwrap()
        .into_iter()
        .enumerate()
        .map(|(k, r)| {
            let s = r.scan;
            LaserScan {
                header: Header {
                    stamp: Time {
                        sec: 100 + i32::try_from(k).unwrap(),
                        nanosec: 0,
                    },
                    frame_id: "laser".to_owned(),
                },
                angle_min: s.angle_min as f32,
                angle_max: s.angle_max() as f32,
                angle_increment: s.angle_increment as f32,
                range_min: s.range_min as f32,
                range_max: s.range_max as f32,
                ranges: s.ranges.iter().map(|&r| r as f32).collect(),
                ..LaserScan::default()
            }
        })
        .collect()
}

struct Robot {
    scans: Publisher<LaserScan>,
    lines: Subscription<LineSegmentList>,
    markers: Subscription<Marker>,
    _node: Node,
    _context: Context,
}

fn robot(domain: u16, reliability: Reliability) -> Robot {
    let dp = DomainParticipantBuilder::new(domain)
        .with_only_networks([IpAddr::V4(Ipv4Addr::LOCALHOST)])
        .build()
        .unwrap();
    let context = Context::from_domain_participant(dp).unwrap();
    let mut node = context
        .new_node(
            NodeName::new("/", "robot").unwrap(),
            NodeOptions::new()
                .enable_rosout(false)
                .start_parameter_services(false),
        )
        .unwrap();
    let scan_qos = QosProfile::publisher_default()
        .reliability(reliability)
        .history(History::KeepLast { depth: 10 });
    let t = node
        .create_topic(
            &Name::parse("/scan").unwrap(),
            msg::laser_scan_type(),
            &scan_qos,
        )
        .unwrap();
    let scans = node.create_publisher(&t, Some(scan_qos)).unwrap();
    let q = output_qos();
    let t = node
        .create_topic(
            &Name::parse("/line_segments").unwrap(),
            msg::line_segment_list_type(msg::LINE_PACKAGE),
            &q,
        )
        .unwrap();
    let lines = node.create_subscription(&t, Some(q.clone())).unwrap();
    let t = node
        .create_topic(
            &Name::parse("/line_markers").unwrap(),
            msg::marker_type(),
            &q,
        )
        .unwrap();
    let markers = node.create_subscription(&t, Some(q)).unwrap();
    Robot {
        scans,
        lines,
        markers,
        _node: node,
        _context: context,
    }
}

/// Waits up to `timeout` for a line list and its marker with the stamp `sec`.
fn wait_outputs(r: &Robot, sec: i32, timeout: Duration) -> Option<(LineSegmentList, Marker)> {
    let end = Instant::now() + timeout;
    let mut list = None;
    let mut marker = None;
    while Instant::now() < end {
        while let Ok(Some((l, _))) = r.lines.take() {
            if l.header.stamp.sec == sec {
                list = Some(l);
            }
        }
        while let Ok(Some((m, _))) = r.markers.take() {
            if m.header.stamp.sec == sec {
                marker = Some(m);
            }
        }
        if list.is_some() && marker.is_some() {
            return list.zip(marker);
        }
        thread::sleep(Duration::from_millis(2));
    }
    None
}

fn round_trip(domain: u16, reliability: Reliability) {
    let config = NodeConfig {
        domain_id: domain,
        only_networks: Some(vec![IpAddr::V4(Ipv4Addr::LOCALHOST)]),
        ..NodeConfig::default()
    };
    let stop = Arc::new(AtomicBool::new(false));
    let s = Arc::clone(&stop);
    let node = thread::spawn(move || {
        let mut node = LineNode::new(&config, processor()).unwrap();
        node.spin(&s, &Limits::default()).unwrap()
    });
    let r = robot(domain, reliability);
    let scans = scans();
    // Discovery: repeat the first scan until its outputs come back (bounded).
    let first = (0..200).find_map(|_| {
        r.scans.publish(scans[0].clone()).unwrap();
        wait_outputs(&r, 100, Duration::from_millis(100))
    });
    assert!(first.is_some(), "no outputs within 20 s: discovery failed");
    let mut expect = processor();
    let mut want = Outputs::default();
    let mut lines = 0;
    for (k, scan) in scans.iter().enumerate() {
        if k > 0 {
            r.scans.publish(scan.clone()).unwrap();
        }
        let (list, marker) = match (k, &first) {
            (0, Some(f)) => f.clone(),
            _ => wait_outputs(&r, scan.header.stamp.sec, Duration::from_secs(5))
                .unwrap_or_else(|| panic!("no outputs for scan {k}")),
        };
        expect.process(scan, &mut want);
        assert_eq!(list, want.lines, "scan {k}");
        assert_eq!(marker, want.marker, "scan {k}");
        assert_eq!(list.header, scan.header);
        lines += list.line_segments.len();
    }
    assert!(lines >= 4 * scans.len(), "{lines} lines");
    // A scan the node cannot use gives nothing; the next one goes through.
    let mut bad = scans[1].clone();
    bad.angle_increment = 0.0;
    bad.header.stamp.sec = 900;
    r.scans.publish(bad).unwrap();
    let mut next = scans[2].clone();
    next.header.stamp.sec = 901;
    r.scans.publish(next).unwrap();
    assert!(wait_outputs(&r, 901, Duration::from_secs(5)).is_some());
    assert!(wait_outputs(&r, 900, Duration::from_millis(200)).is_none());
    stop.store(true, Ordering::Relaxed);
    let counts = node.join().unwrap();
    assert_eq!(counts.skipped_geometry, 1);
    assert_eq!(counts.extracted, counts.seen - 1);
    assert!(counts.extracted > scans.len() as u64);
}

fn domain(offset: u16) -> u16 {
    // Away from the default domain and from other runs on the machine.
    150 + 2 * u16::try_from(std::process::id() % 40).unwrap() + offset
}

#[test]
fn reliable_publisher_round_trip_on_loopback() {
    round_trip(
        domain(0),
        Reliability::Reliable {
            when_full: WhenFull::Wait(Duration::from_millis(100)),
        },
    );
}

#[test]
fn best_effort_publisher_round_trip_on_loopback() {
    round_trip(domain(1), Reliability::BestEffort);
}
