//! MCAP and Foxglove on the command line: `extract -o out.mcap`, `convert` to and from MCAP,
//! `view` served on loopback and watched by a WebSocket client, and bad MCAP input.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::HashMap;
use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use foxglove::messages::{FrameTransform, LaserScan, SceneUpdate};
use laserlines_foxglove::{McapReadOptions, read};
use laserlines_io::ScanRecord;
use prost::Message as _;
use tungstenite::client::IntoClientRequest;
use tungstenite::{Message, WebSocket};

mod common;
use common::{bin, excerpt, served_port, tmp};

const EXCERPT_SCANS: usize = 40;

fn run(cmd: &mut Command) -> Output {
    let o = cmd.output().expect("the laserlines binary runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "panic: {err}");
    o
}

fn ok(cmd: &mut Command) -> Output {
    let o = run(cmd);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

fn direct() -> Vec<ScanRecord> {
    laserlines_io::open(&excerpt(), None)
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap()
}

fn from_mcap(path: &Path) -> Vec<ScanRecord> {
    read::open(path, &McapReadOptions::default())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap()
}

/// Every message of an MCAP file by topic, with the stock reader of the `mcap` crate.
fn messages(path: &Path) -> HashMap<String, Vec<Vec<u8>>> {
    let bytes = std::fs::read(path).unwrap();
    let mut out: HashMap<String, Vec<Vec<u8>>> = HashMap::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        out.entry(m.channel.topic.clone())
            .or_default()
            .push(m.data.into_owned());
    }
    out
}

/// The scans must agree: stamps, poses, geometry, and every valid range (invalid ranges are
/// written as NaN, "no return").
fn assert_same_scans(got: &[ScanRecord], want: &[ScanRecord]) {
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.scan.stamp, w.scan.stamp);
        let (gp, wp) = (g.pose.unwrap(), w.pose.unwrap());
        assert_eq!((gp.x, gp.y), (wp.x, wp.y));
        assert!((gp.theta - wp.theta).abs() < 1e-12);
        assert_eq!(g.scan.angle_min, w.scan.angle_min);
        assert!((g.scan.angle_increment - w.scan.angle_increment).abs() < 1e-15);
        assert_eq!(
            (g.scan.range_min, g.scan.range_max),
            (w.scan.range_min, w.scan.range_max)
        );
        let window = w.scan.range_window(None);
        for (a, b) in g.scan.ranges.iter().zip(&w.scan.ranges) {
            if window.contains(*b) {
                assert_eq!(a, b);
            } else {
                assert!(a.is_nan());
            }
        }
    }
}

#[test]
fn extract_to_mcap_writes_scans_lines_and_poses() {
    let out = tmp("extract.mcap");
    let jsonl = tmp("extract.jsonl");
    ok(bin().arg("extract").arg(excerpt()).arg("-o").arg(&out));
    ok(bin().arg("extract").arg(excerpt()).arg("-o").arg(&jsonl));
    let by_topic = messages(&out);
    assert_eq!(by_topic["/scan"].len(), EXCERPT_SCANS);
    assert_eq!(by_topic["/lines"].len(), EXCERPT_SCANS);
    // The excerpt has wheel odometry: per scan `world -> odom`, `odom -> base_link` (REP 105)
    // and the laser at the robot.
    assert_eq!(by_topic["/tf"].len(), 3 * EXCERPT_SCANS);
    let frames: Vec<(String, String)> = by_topic["/tf"][..3]
        .iter()
        .map(|m| {
            let t = FrameTransform::decode(m.as_slice()).unwrap();
            (t.parent_frame_id, t.child_frame_id)
        })
        .collect();
    assert_eq!(
        frames,
        [
            ("world", "odom"),
            ("odom", "base_link"),
            ("base_link", "laser")
        ]
        .map(|(a, b)| (a.to_owned(), b.to_owned()))
    );
    // The lines are those of the JSONL output, end point for end point.
    let text = std::fs::read_to_string(&jsonl).unwrap();
    for (line, update) in text.lines().zip(&by_topic["/lines"]) {
        let want: serde_json::Value = serde_json::from_str(line).unwrap();
        let update = SceneUpdate::decode(update.as_slice()).unwrap();
        let points = &update.entities[0].lines[0].points;
        let want = want["lines"].as_array().unwrap();
        assert_eq!(points.len(), 2 * want.len());
        for (pair, l) in points.chunks(2).zip(want) {
            assert_eq!(pair[0].x, l["start"][0].as_f64().unwrap());
            assert_eq!(pair[0].y, l["start"][1].as_f64().unwrap());
            assert_eq!(pair[1].x, l["end"][0].as_f64().unwrap());
            assert_eq!(pair[1].y, l["end"][1].as_f64().unwrap());
        }
    }
    // Our reader gives back the scans with their stamps and poses.
    assert_same_scans(&from_mcap(&out), &direct());
}

#[test]
fn convert_to_mcap_and_back() {
    let mcap = tmp("convert.mcap");
    let back = tmp("back.jsonl");
    let o = ok(bin().arg("convert").arg(excerpt()).arg(&mcap));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("40 scans written"), "{err}");
    let by_topic = messages(&mcap);
    assert_eq!(by_topic["/scan"].len(), EXCERPT_SCANS);
    assert!(!by_topic.contains_key("/lines"));
    let first = LaserScan::decode(by_topic["/scan"][0].as_slice()).unwrap();
    assert_eq!(first.frame_id, "laser");
    assert_same_scans(&from_mcap(&mcap), &direct());
    ok(bin().arg("convert").arg(&mcap).arg(&back));
    let again: Vec<ScanRecord> = laserlines_io::open(&back, None)
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_same_scans(&again, &direct());
}

#[test]
fn bad_mcap_input_is_a_clean_error_naming_file_and_byte() {
    let good = tmp("good.mcap");
    ok(bin().arg("convert").arg(excerpt()).arg(&good));
    let bytes = std::fs::read(&good).unwrap();
    let cut = tmp("cut.mcap");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let o = run(bin()
        .arg("extract")
        .arg(&cut)
        .arg("-o")
        .arg(tmp("cut.jsonl")));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("cut.mcap: byte "), "{err}");
    assert!(err.contains("truncated"), "{err}");
    let o = run(bin()
        .arg("convert")
        .arg(&good)
        .arg(tmp("x.jsonl"))
        .args(["--topic", "/nope"]));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("a channel on topic /nope"), "{err}");
    assert!(err.contains("/scan (foxglove.LaserScan)"), "{err}");
}

// --- view ------------------------------------------------------------------------------------

const DEADLINE: Duration = Duration::from_secs(30);

/// Kills the child when the test ends, however it ends.
struct Child(std::process::Child);

impl Drop for Child {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn read_ws(ws: &mut WebSocket<TcpStream>) -> Option<Message> {
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

/// `view` of the bundled excerpt with `args`, its stderr after the first status line, and
/// the port that line names.
fn spawn_view(args: &[&str]) -> (Child, BufReader<std::process::ChildStderr>, u16) {
    let mut child = Child(
        bin()
            .arg("view")
            .arg(excerpt())
            .args(["--port", "0"])
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    // The status lines are on stderr: the first says where it serves.
    let mut stderr = BufReader::new(child.0.stderr.take().unwrap());
    let mut first = String::new();
    stderr.read_line(&mut first).unwrap();
    let port = served_port(&first);
    (child, stderr, port)
}

#[test]
fn a_client_that_fails_its_handshake_is_no_failed_run() {
    let (mut child, mut stderr, port) = spawn_view(&["--no-wait", "--rate", "2"]);
    // A plain HTTP request, no WebSocket upgrade: the server drops the client.
    let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    std::io::Write::write_all(&mut stream, b"GET / HTTP/1.1\r\nHost: x\r\n\r\n").unwrap();
    drop(stream);
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut rest).unwrap();
    let status = child.0.wait().unwrap();
    assert!(status.success(), "{rest}");
    // Said, but not as the error a failed run ends with.
    assert!(
        rest.contains("laserlines: error (the run goes on): "),
        "{rest}"
    );
    assert!(!rest.contains("laserlines: error: "), "{rest}");
    assert!(rest.contains("40 scans"), "{rest}");
}

#[test]
fn view_serves_scans_and_lines_to_a_foxglove_client() {
    let start = Instant::now();
    let (mut child, mut stderr, port) = spawn_view(&["--rate", "20"]);
    // The rest must be read, or the child blocks on a full pipe.
    std::thread::spawn(move || std::io::copy(&mut stderr, &mut std::io::sink()));

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
    let mut ws = tungstenite::client(request, stream).unwrap().0;

    let mut subscriptions: HashMap<u32, String> = HashMap::new();
    let (mut scan, mut lines) = (None, None);
    while scan.is_none() || lines.is_none() {
        assert!(
            start.elapsed() < DEADLINE,
            "no scan and scene update in time"
        );
        match read_ws(&mut ws) {
            Some(Message::Text(t)) => {
                let v: serde_json::Value = serde_json::from_str(t.as_str()).unwrap();
                if v["op"] != "advertise" {
                    continue;
                }
                let mut subs = Vec::new();
                for c in v["channels"].as_array().unwrap() {
                    let sub = subscriptions.len() as u32 + 1;
                    subscriptions.insert(sub, c["topic"].as_str().unwrap().to_owned());
                    subs.push(serde_json::json!({"id": sub, "channelId": c["id"]}));
                }
                let msg = serde_json::json!({"op": "subscribe", "subscriptions": subs});
                ws.send(Message::Text(msg.to_string().into())).unwrap();
            }
            Some(Message::Binary(b)) if b.len() >= 13 && b[0] == 1 => {
                let sub = u32::from_le_bytes(b[1..5].try_into().unwrap());
                match subscriptions.get(&sub).map(String::as_str) {
                    Some("/scan") if scan.is_none() => {
                        scan = Some(LaserScan::decode(&b[13..]).unwrap());
                    }
                    Some("/lines") if lines.is_none() => {
                        lines = Some(SceneUpdate::decode(&b[13..]).unwrap());
                    }
                    _ => {}
                }
            }
            _ => {}
        }
    }
    // The server ends the replay with a close frame (after the last scan, at 20x in about
    // 0.2 s, and half a second for the last messages to leave).
    let mut closed = false;
    while !closed {
        assert!(start.elapsed() < DEADLINE, "no close frame in time");
        match ws.read() {
            Ok(Message::Close(_)) => closed = true,
            Ok(_) => {}
            Err(tungstenite::Error::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) => {}
            Err(e) => panic!("the socket ended without a close frame: {e}"),
        }
    }
    let scan = scan.unwrap();
    assert_eq!(scan.ranges.len(), 682);
    assert_eq!(scan.frame_id, "laser");
    let lines = lines.unwrap();
    assert_eq!(lines.entities[0].id, "lines");
    assert!(!lines.entities[0].lines[0].points.is_empty());
    // The replay ends by itself: 40 scans about 0.1 s apart at 20x take well under a second.
    loop {
        if let Some(status) = child.0.try_wait().unwrap() {
            assert!(status.success(), "{status}");
            break;
        }
        assert!(start.elapsed() < DEADLINE, "view did not end");
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Starts `view` on the excerpt with `args`, waits for its first status line, interrupts it
/// (SIGINT, as Ctrl-C does) after `after`, and returns its exit status and whole stderr.
#[cfg(unix)]
fn interrupted_view(args: &[&str], after: Duration) -> (std::process::ExitStatus, String) {
    use std::io::Read;
    let mut child = Child(
        bin()
            .arg("view")
            .arg(excerpt())
            .args(["--port", "0"])
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let mut stderr = BufReader::new(child.0.stderr.take().unwrap());
    let mut text = String::new();
    stderr.read_line(&mut text).unwrap();
    assert!(text.contains("serving"), "{text}");
    let rest = std::thread::spawn(move || {
        let mut s = String::new();
        stderr.read_to_string(&mut s).unwrap();
        s
    });
    std::thread::sleep(after);
    let pid = child.0.id().to_string();
    let kill = Command::new("kill").args(["-INT", &pid]).status().unwrap();
    assert!(kill.success());
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.0.try_wait().unwrap() {
            break status;
        }
        assert!(start.elapsed() < DEADLINE, "view did not end on SIGINT");
        std::thread::sleep(Duration::from_millis(50));
    };
    text.push_str(&rest.join().unwrap());
    (status, text)
}

#[cfg(unix)]
#[test]
fn ctrl_c_ends_view_with_its_summary() {
    // Replaying in a loop at real time (40 scans 0.1 s apart): only the interrupt ends it.
    let (status, text) = interrupted_view(&["--no-wait", "--loop"], Duration::from_millis(1500));
    assert!(status.success(), "{status}: {text}");
    assert!(text.contains("laserlines: interrupted"), "{text}");
    let summary = text
        .lines()
        .find(|l| l.contains("replayed in"))
        .unwrap_or_else(|| panic!("no summary in {text}"));
    // About 15 scans in 1.5 s; at least one, fewer than a whole pass.
    let scans: usize = summary
        .split(": ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("{summary}"));
    assert!((1..EXCERPT_SCANS).contains(&scans), "{summary}");
    // Waiting for a viewer that never comes.
    let (status, text) = interrupted_view(&[], Duration::from_millis(300));
    assert!(status.success(), "{status}: {text}");
    assert!(
        text.contains("interrupted before a viewer subscribed"),
        "{text}"
    );
}

#[test]
fn view_refuses_an_empty_input_before_serving_and_sums_up_a_log_cut_short() {
    let empty = tmp("view-empty.jsonl");
    std::fs::write(&empty, "").unwrap();
    let o = bin()
        .arg("view")
        .arg(&empty)
        .args(["--no-wait", "--port", "0"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("view-empty.jsonl: no scans to read"), "{err}");
    assert!(!err.contains("serving"), "served an empty input: {err}");

    // Two whole scans, then a line cut short.
    let scan = r#"{"angle_min": -1.0, "angle_increment": 0.1, "range_min": 0.02, "range_max": 5.6, "ranges": [1.0, 1.0, 1.0, 1.0, 1.0]}"#;
    let cut = tmp("view-cut.jsonl");
    std::fs::write(&cut, format!("{scan}\n{scan}\n{}", &scan[..40])).unwrap();
    let o = bin()
        .arg("view")
        .arg(&cut)
        .args(["--no-wait", "--rate", "0", "--port", "0"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("view-cut.jsonl: 2 scans, 0 lines replayed before the error"),
        "{err}"
    );
    assert!(err.contains("view-cut.jsonl:3"), "{err}");
}
