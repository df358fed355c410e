//! The live server on loopback: a WebSocket client speaking the Foxglove protocol subscribes
//! to `/scan`, `/lines` and a scene channel (`/sectors`) and decodes what it gets. Bounded in time: every read has a
//! timeout and the whole exchange a deadline.

#![cfg(feature = "live")]
#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::collections::HashMap;
use std::net::TcpStream;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use foxglove::messages::{LaserScan, SceneUpdate};
use laserlines::math::Isometry2;
use laserlines::math::Matrix2;
use laserlines::math::Point2;
use laserlines::{Line, Scan};
use laserlines_foxglove::live::LiveServer;
use laserlines_foxglove::sectors::{SECTORS_TOPIC, sectors_update};
use laserlines_io::{Pose2, ScanRecord};
use laserlines_nav::{Sector, SectorParams, select_objects};
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

/// What a viewer got: the schema and the first message of each topic watched.
type Seen = HashMap<String, (String, Vec<u8>)>;

/// Subscribes to every channel advertised and keeps the first message of each of `wanted`.
fn watch(port: u16, wanted: &[&str]) -> Seen {
    let start = Instant::now();
    let mut ws = connect(port);
    let mut schemas: HashMap<String, String> = HashMap::new();
    let mut subscribed: HashMap<u32, String> = HashMap::new();
    let mut seen = Seen::new();
    while wanted.iter().any(|t| !seen.contains_key(*t)) {
        assert!(
            start.elapsed() < DEADLINE,
            "not every one of {wanted:?} in time: {:?}",
            seen.keys()
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
                        schemas.insert(topic.clone(), c["schemaName"].as_str().unwrap().into());
                        subscribed.insert(sub, topic);
                        subs.push(serde_json::json!({"id": sub, "channelId": id}));
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
                if let Some(topic) = subscribed.get(&sub) {
                    seen.entry(topic.clone())
                        .or_insert_with(|| (schemas[topic].clone(), b[13..].to_vec()));
                }
            }
            _ => {}
        }
    }
    let _ = ws.close(None);
    seen
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
    let seen = watch(port, &["/scan", "/lines"]);
    stop.store(true, Ordering::Relaxed);
    publisher.join().unwrap();

    assert_eq!(seen["/scan"].0, "foxglove.LaserScan");
    assert_eq!(seen["/lines"].0, "foxglove.SceneUpdate");
    let scan = LaserScan::decode(seen["/scan"].1.as_slice()).unwrap();
    let lines = SceneUpdate::decode(seen["/lines"].1.as_slice()).unwrap();
    assert_eq!(scan.frame_id, "laser");
    assert_eq!(scan.ranges[1], 2.0);
    assert!(scan.ranges[2].is_nan(), "beyond range_max");
    assert_eq!(scan.start_angle, -0.5);
    let e = &lines.entities[0];
    assert_eq!((e.frame_id.as_str(), e.id.as_str()), ("laser", "lines"));
    let p = &e.lines[0].points;
    assert_eq!(p.len(), 2);
    assert_eq!((p[0].x, p[0].y, p[1].x, p[1].y), (1.0, -0.5, 1.0, 0.5));
}

#[test]
fn a_viewer_on_loopback_receives_the_sector_scene() {
    // Scene topics must be new ones.
    for topics in [&["/lines"][..], &["/sectors", "/sectors"]] {
        let e = LiveServer::start_with_scenes("127.0.0.1", 0, topics).unwrap_err();
        assert!(e.to_string().contains(topics[0]), "{e}");
    }
    let server = LiveServer::start_with_scenes("127.0.0.1", 0, &[SECTORS_TOPIC]).unwrap();
    let port = server.port();
    // A wall 1.2 m ahead, across the front sector; a short one on the left.
    let lines = [line((1.2, -0.4), (1.2, 0.6)), line((-0.3, 0.8), (0.4, 0.8))];
    let objects = select_objects(&lines, &Isometry2::identity(), &SectorParams::default());
    let update = sectors_update(&objects, "laser", None, 0.0);
    let e = server
        .publish_scene("/elsewhere", &update, 1.0)
        .unwrap_err();
    assert!(e.to_string().contains("/elsewhere"), "{e}");
    let stop = Arc::new(AtomicBool::new(false));
    let publisher = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            let start = Instant::now();
            assert!(server.wait_for_viewer(Some(DEADLINE)), "no viewer");
            let record = ScanRecord::new(Scan::new(-0.5, 0.25, 0.1, 8.0, vec![1.0; 5]).unwrap());
            let mut t = 50.0;
            while !stop.load(Ordering::Relaxed) && start.elapsed() < DEADLINE {
                server.publish(&record, &lines, t);
                let update = sectors_update(&objects, "laser", None, t);
                server.publish_scene(SECTORS_TOPIC, &update, t).unwrap();
                t += 0.1;
                std::thread::sleep(Duration::from_millis(20));
            }
            server.stop();
        })
    };
    let seen = watch(port, &["/sectors"]);
    stop.store(true, Ordering::Relaxed);
    publisher.join().unwrap();

    assert_eq!(seen["/sectors"].0, "foxglove.SceneUpdate");
    let got = SceneUpdate::decode(seen["/sectors"].1.as_slice()).unwrap();
    let e = &got.entities[0];
    assert_eq!((e.frame_id.as_str(), e.id.as_str()), ("laser", "sectors"));
    // No footprint: the sector bounds only (two rays per sector), then one thick line per
    // object.
    assert_eq!(e.lines[0].points.len(), 12);
    assert_eq!(e.lines.len(), 1 + 2);
    let front = objects.get(Sector::Front).unwrap();
    assert!((front.distance_m - 1.2).abs() < 1e-12);
    assert!(objects.get(Sector::Left).is_some() && objects.get(Sector::Right).is_none());
    let label = e.metadata.iter().find(|kv| kv.key == "front").unwrap();
    assert!(label.value.starts_with("front: 1.20 m"), "{}", label.value);
    let p = &e.spheres[1]
        .pose
        .as_ref()
        .unwrap()
        .position
        .as_ref()
        .unwrap();
    assert_eq!((p.x, p.y), (front.nearest.x, front.nearest.y));
    assert!(e.metadata.iter().all(|kv| kv.key != "right"));
}
