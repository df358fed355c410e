//! The live server on loopback: a WebSocket client speaking the Foxglove protocol subscribes
//! to `/scan` and `/lines` and decodes what it gets. Bounded in time: every read has a
//! timeout and the whole exchange a deadline.

#![cfg(feature = "live")]
#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::collections::HashMap;
use std::net::TcpStream;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use foxglove::messages::{LaserScan, SceneUpdate};
use laserlines::math::Matrix2;
use laserlines::math::Point2;
use laserlines::{Line, Scan};
use laserlines_foxglove::live::LiveServer;
use laserlines_io::{Pose2, ScanRecord};
use prost::Message as _;
use tungstenite::client::IntoClientRequest;
use tungstenite::{Message, WebSocket};

const DEADLINE: Duration = Duration::from_secs(20);

fn connect(port: u16) -> WebSocket<TcpStream> {
    let stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_millis(200)))
        .unwrap();
    let mut request = format!("ws://127.0.0.1:{port}")
        .into_client_request()
        .unwrap();
    request
        .headers_mut()
        .insert("Sec-WebSocket-Protocol", "foxglove.sdk.v1".parse().unwrap());
    tungstenite::client(request, stream).unwrap().0
}

fn read(ws: &mut WebSocket<TcpStream>) -> Option<Message> {
    match ws.read() {
        Ok(m) => Some(m),
        Err(tungstenite::Error::Io(e))
            if matches!(
                e.kind(),
                std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
            ) =>
        {
            None
        }
        Err(e) => panic!("websocket: {e}"),
    }
}

/// What a viewer got: one decoded scan and one decoded scene update.
struct Seen {
    /// The first `/scan` message.
    scan: LaserScan,
    /// The first `/lines` message.
    lines: SceneUpdate,
}

/// Subscribes to `/scan` and `/lines` and decodes the first message of each.
fn watch(port: u16) -> Seen {
    let start = Instant::now();
    let mut ws = connect(port);
    let mut topics: HashMap<u64, String> = HashMap::new();
    let mut subscribed: HashMap<u32, String> = HashMap::new();
    let (mut scan, mut lines) = (None, None);
    while scan.is_none() || lines.is_none() {
        assert!(
            start.elapsed() < DEADLINE,
            "no scan and scene update in time"
        );
        match read(&mut ws) {
            Some(Message::Text(t)) => {
                let v: serde_json::Value = serde_json::from_str(t.as_str()).unwrap();
                if v["op"] == "advertise" {
                    let mut subs = Vec::new();
                    for c in v["channels"].as_array().unwrap() {
                        let id = c["id"].as_u64().unwrap();
                        let topic = c["topic"].as_str().unwrap().to_owned();
                        let sub = subscribed.len() as u32 + 1;
                        if topic == "/scan" {
                            assert_eq!(c["schemaName"], "foxglove.LaserScan");
                        }
                        if topic == "/lines" {
                            assert_eq!(c["schemaName"], "foxglove.SceneUpdate");
                        }
                        subscribed.insert(sub, topic.clone());
                        subs.push(serde_json::json!({"id": sub, "channelId": id}));
                        topics.insert(id, topic);
                    }
                    let msg = serde_json::json!({"op": "subscribe", "subscriptions": subs});
                    ws.send(Message::Text(msg.to_string().into())).unwrap();
                }
            }
            Some(Message::Binary(b)) => {
                // Message data: opcode 1, subscription id (u32 LE), log time (u64 LE), payload.
                if b.first() != Some(&1) || b.len() < 13 {
                    continue;
                }
                let sub = u32::from_le_bytes(b[1..5].try_into().unwrap());
                let payload = &b[13..];
                match subscribed.get(&sub).map(String::as_str) {
                    Some("/scan") if scan.is_none() => {
                        scan = Some(LaserScan::decode(payload).unwrap());
                    }
                    Some("/lines") if lines.is_none() => {
                        lines = Some(SceneUpdate::decode(payload).unwrap());
                    }
                    _ => {}
                }
            }
            _ => {}
        }
    }
    let _ = ws.close(None);
    Seen {
        scan: scan.unwrap(),
        lines: lines.unwrap(),
    }
}

fn line(start: (f64, f64), end: (f64, f64)) -> Line {
    Line {
        start: Point2::new(start.0, start.1),
        end: Point2::new(end.0, end.1),
        r: 1.0,
        alpha: 0.0,
        first: 0,
        last: 3,
        points: 4,
        rms: 0.0,
        covariance: Matrix2::zeros(),
    }
}

#[test]
fn a_viewer_on_loopback_receives_scans_and_lines() {
    let server = LiveServer::start("127.0.0.1", 0).unwrap();
    let port = server.port();
    assert_ne!(port, 0);
    let stop = Arc::new(AtomicBool::new(false));
    let publisher = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            let start = Instant::now();
            assert!(
                server.wait_for_viewer(Some(DEADLINE)),
                "no viewer subscribed"
            );
            let mut record = ScanRecord::new(
                Scan::new(-0.5, 0.25, 0.1, 8.0, vec![1.0, 2.0, 9.0, 1.5, 1.0]).unwrap(),
            );
            record.pose = Some(Pose2::new(1.0, 2.0, 0.5));
            let lines = [line((1.0, -0.5), (1.0, 0.5))];
            // Publish until the viewer has what it needs (its /lines subscription may come a
            // moment after /scan's).
            let mut k = 0.0;
            while !stop.load(Ordering::Relaxed) && start.elapsed() < DEADLINE {
                server.publish(&record, &lines, 100.0 + k);
                k += 0.1;
                std::thread::sleep(Duration::from_millis(20));
            }
            server.stop();
        })
    };
    let seen = watch(port);
    stop.store(true, Ordering::Relaxed);
    publisher.join().unwrap();

    assert_eq!(seen.scan.frame_id, "laser");
    assert_eq!(seen.scan.ranges[1], 2.0);
    assert!(seen.scan.ranges[2].is_nan(), "beyond range_max");
    assert_eq!(seen.scan.start_angle, -0.5);
    let e = &seen.lines.entities[0];
    assert_eq!((e.frame_id.as_str(), e.id.as_str()), ("laser", "lines"));
    let p = &e.lines[0].points;
    assert_eq!(p.len(), 2);
    assert_eq!((p[0].x, p[0].y, p[1].x, p[1].y), (1.0, -0.5, 1.0, 0.5));
}
