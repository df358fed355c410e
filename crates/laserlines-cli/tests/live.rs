//! `laserlines live` against `laserlines hokuyo-emulator` over TCP, as a user runs them:
//! the emulator's address from its first line, `live --scans N -o lines.jsonl`, one JSON
//! object per scan, a summary naming the scans, no scan dropped, QT at the end; with
//! `--sectors`, the sector objects of every scan in the MCAP recording (read back) and in
//! the live view (watched by a Foxglove WebSocket client).

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::collections::HashMap;
use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::path::PathBuf;
use std::process::Stdio;
use std::time::{Duration, Instant};

use foxglove::messages::SceneUpdate;
use laserlines::math::Point2;
use laserlines_nav::sectors::{Sector, SectorObjects, SectorParams, select_segments};
use prost::Message as _;
use tungstenite::Message;
use tungstenite::client::IntoClientRequest;

mod common;
use common::{bin, served_port};

const DEADLINE: Duration = Duration::from_secs(60);

/// A child process killed when the test ends, however it ends.
struct Child(std::process::Child);

impl Drop for Child {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// An emulated UST-10LX on a free local port, and its address from its first line.
fn emulator() -> (Child, String) {
    emulator_for("120")
}

/// [`emulator`] serving for `seconds`.
fn emulator_for(seconds: &str) -> (Child, String) {
    emulator_with(&["--duration", seconds])
}

/// The emulated UST-10LX on a free port with `args`, and its address.
fn emulator_with(args: &[&str]) -> (Child, String) {
    let mut child = Child(
        bin()
            .args(["hokuyo-emulator", "--model", "ust-10lx"])
            .args(["--tcp", "127.0.0.1:0"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let mut first = String::new();
    BufReader::new(child.0.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    let addr = first.trim().rsplit(" on ").next().unwrap().to_owned();
    (child, addr)
}

fn tmp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("laserlines-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn live_reads_the_emulated_ust10lx_and_writes_lines_per_scan() {
    let (_emulator, addr) = emulator();
    let dir = tmp_dir("live");
    let out = dir.join("lines.jsonl");
    let run = bin()
        .args(["live", &addr, "--scans", "25", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(stderr.contains("UST-10LX"), "{stderr}");
    assert!(
        stderr.contains("25 scans") && stderr.contains("dropped: none"),
        "{stderr}"
    );
    // A run shorter than a second still has its rate (40 scans/s), not 0.
    assert!(!stderr.contains("; 0.0 scans/s"), "{stderr}");
    let text = std::fs::read_to_string(&out).unwrap();
    let scans: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(scans.len(), 25);
    let stamps: Vec<f64> = scans.iter().map(|s| s["stamp"].as_f64().unwrap()).collect();
    assert!(stamps.windows(2).all(|w| w[1] > w[0]));
    // The arena's walls give lines.
    assert!(
        scans
            .iter()
            .all(|s| !s["lines"].as_array().unwrap().is_empty())
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_duration_ends_a_run_whose_sensor_went_away() {
    // The sensor serves for 1 s and is gone; the run, given 7 s, ends then with its summary
    // (it used to wait for the sensor for ever), and tells of the sensor's absence meanwhile.
    let (_emulator, addr) = emulator_for("1");
    let mut live = Child(
        bin()
            .args(["live", &addr, "--duration", "7"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let start = Instant::now();
    let status = loop {
        if let Some(status) = live.0.try_wait().unwrap() {
            break status;
        }
        assert!(
            start.elapsed() < DEADLINE,
            "live still running after the sensor left"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut live.0.stderr.take().unwrap(), &mut stderr).unwrap();
    assert!(status.success(), "{stderr}");
    // The summary's rate is the run's average: the scans over the run's seconds, however
    // fast the sensor served before it went away.
    let summary = stderr
        .lines()
        .find(|l| l.contains(" lines in ") && l.contains(" on average; at the end: "))
        .unwrap_or_else(|| panic!("no summary: {stderr}"));
    let number_before = |text: &str, unit: &str| -> f64 {
        let head = &text[..text.find(unit).unwrap()];
        head.rsplit([' ', ',']).next().unwrap().parse().unwrap()
    };
    let (scans, secs) = (
        number_before(summary, " scans, "),
        number_before(summary, " s, "),
    );
    let average = number_before(summary, " scans/s on average");
    assert!(scans > 0.0 && secs >= 6.5, "{summary}");
    assert!(
        (average * secs - scans).abs() <= 0.05 * secs + 0.5,
        "{summary}"
    );
    // Lost at about 1 s; still away 5 s later.
    assert!(
        stderr.contains("sensor link lost; reconnecting"),
        "{stderr}"
    );
    assert!(stderr.contains("sensor still away after 5 s"), "{stderr}");
    // A silence of zero would lose the link at every read: refused.
    let o = bin()
        .args(["live", &addr, "--silence", "0"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--silence must be seconds, more than 0 up to 1e9, got 0"),
        "{err}"
    );
}

#[test]
fn a_silence_shorter_than_two_scan_periods_is_refused() {
    // The emulated UST-10LX scans every 25 ms: the link would seem lost between two scans.
    // Said once the sensor has described itself.
    let (_emulator, addr) = emulator_with(&[]);
    let o = bin()
        .args(["live", &addr, "--silence", "0.02", "--scans", "1"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains(
            "--silence 0.02 s is shorter than two of this sensor's scan periods (2 x 0.025 s)"
        ),
        "{err}"
    );
}

#[test]
fn the_duration_ends_a_run_whose_sensor_is_still_starting() {
    let out = |tag: &str| {
        std::env::temp_dir().join(format!(
            "laserlines-starting-{tag}-{}.jsonl",
            std::process::id()
        ))
    };
    // Replies 40 ms late: the start takes most of a second, and the stop during it ends the
    // run once it is done, with QT.
    let (_emulator, addr) = emulator_with(&["--reply-delay-ms", "40"]);
    let o = bin()
        .args(["live", &addr, "--duration", "0.1", "-o"])
        .arg(out("quick"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("--duration ran out while the sensor is starting: ending once it is done")
            && err.contains("stopped while the sensor was starting: no scan read, nothing written"),
        "{err}"
    );
    assert!(!out("quick").exists());
    // Every reply a second late: the start takes many seconds; the run ends 2 s after the
    // stop, without QT, and says so.
    let (_emulator, addr) = emulator_with(&["--reply-delay-ms", "1000"]);
    let o = bin()
        .args(["live", &addr, "--duration", "1", "-o"])
        .arg(out("slow"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains(
            "the sensor was not done starting 2 s after the stop: ended without QT, nothing \
             written"
        ),
        "{err}"
    );
    assert!(!out("slow").exists());
}

#[test]
fn live_refuses_one_file_for_the_lines_and_the_recording() {
    let dir = std::env::temp_dir().join(format!("laserlines-live-one-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Refused before the sensor (none at this address) is opened.
    let o = bin()
        .args(["live", "127.0.0.1:9", "-o"])
        .arg(dir.join("s.mcap"))
        .arg("--record")
        .arg(dir.join(".").join("s.mcap"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("s.mcap: -o and --record name one file"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
    // Options that would do nothing, refused before the sensor is opened.
    for (args, says) in [
        (
            &["live", "127.0.0.1:9", "--baud", "9600"][..],
            "--baud 9600: 127.0.0.1:9 is a sensor on the network",
        ),
        (
            &["live", "/dev/nonexistent-tty", "--baud", "0"][..],
            "must be from 1 to 4294967295, got 0",
        ),
        (
            &["live", "127.0.0.1:9", "--port", "9000"][..],
            "required arguments were not provided",
        ),
        (
            &["live", "127.0.0.1:9", "-o", "-", "--sectors"][..],
            "--sectors prints the sector objects on standard output, which -o - takes",
        ),
        (
            &["hokuyo-emulator", "--down-for", "3"][..],
            "--drop-after <DROP_AFTER>",
        ),
    ] {
        let o = bin().args(args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

#[test]
fn live_tells_when_the_sensor_leaves_and_comes_back() {
    // The sensor drops the link after 20 scans (half a second) and is unreachable for 1 s.
    let (_emulator, addr) = emulator_with(&["--drop-after", "20", "--down-for", "1"]);
    let o = bin()
        .args(["live", &addr, "--scans", "30"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let lost = err.find("laserlines: warning: sensor link lost; reconnecting");
    let back = err.find("laserlines: info: sensor link back after ");
    assert!(lost.is_some() && back > lost, "{err}");
    assert!(
        err.contains("30 scans, ") && err.contains("reconnects 1"),
        "{err}"
    );
}

#[test]
fn live_counts_the_scans_lost_to_an_outage_still_going_on_at_the_end() {
    // 20 scans (half a second at 40 Hz), then the sensor is away for longer than the run:
    // about 2.5 s of scans, 100, are lost, and the summary counts them.
    let (_emulator, addr) = emulator_with(&["--drop-after", "20", "--down-for", "60"]);
    let o = bin()
        .args(["live", &addr, "--duration", "3"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let summary = err.lines().rfind(|l| l.contains(" scans, ")).expect(&err);
    let lost: u64 = summary
        .split(", ")
        .find_map(|part| part.strip_suffix(" disconnected"))
        .and_then(|n| n.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .expect(summary);
    assert!((60..=140).contains(&lost), "{lost} lost: {summary}");
}

/// The messages of each topic of an MCAP file, with their log times and schema names, read
/// by the `mcap` crate's own reader.
fn mcap_topics(bytes: &[u8]) -> HashMap<String, Vec<(u64, String, Vec<u8>)>> {
    let mut out: HashMap<String, Vec<(u64, String, Vec<u8>)>> = HashMap::new();
    for m in mcap::MessageStream::new(bytes).unwrap() {
        let m = m.unwrap();
        let schema = m.channel.schema.as_ref().unwrap().name.clone();
        out.entry(m.channel.topic.clone()).or_default().push((
            m.log_time,
            schema,
            m.data.into_owned(),
        ));
    }
    out
}

/// The objects of the lines of a `/lines` scene update (one `LINE_LIST`, two points per
/// line), selected afresh.
fn objects_of(lines: &SceneUpdate) -> SectorObjects {
    let points = &lines.entities[0].lines[0].points;
    let segments: Vec<(Point2, Point2)> = points
        .chunks(2)
        .map(|p| (Point2::new(p[0].x, p[0].y), Point2::new(p[1].x, p[1].y)))
        .collect();
    select_segments(&segments, &SectorParams::default())
}

/// A `/sectors` update holds the objects given: frame `laser`, the bounds, then for each
/// object in sector order its piece as a line, its nearest point as a sphere and its label.
fn assert_scene_holds(update: &SceneUpdate, objects: &SectorObjects) {
    let e = &update.entities[0];
    assert_eq!((e.frame_id.as_str(), e.id.as_str()), ("laser", "sectors"));
    assert_eq!(e.lines[0].points.len(), 12, "two rays per sector bound");
    let present: Vec<Sector> = Sector::ALL
        .into_iter()
        .filter(|&s| objects.get(s).is_some())
        .collect();
    assert_eq!(e.lines.len(), 1 + present.len());
    assert_eq!(e.spheres.len(), present.len());
    for (k, s) in present.into_iter().enumerate() {
        let o = objects.get(s).unwrap();
        let piece = &e.lines[1 + k].points;
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(close(piece[0].x, o.start.x) && close(piece[0].y, o.start.y));
        assert!(close(piece[1].x, o.end.x) && close(piece[1].y, o.end.y));
        let label = &e.metadata[k];
        assert_eq!(label.key, s.name());
        assert!(
            label
                .value
                .starts_with(&format!("{}: {:.2} m", s.name(), o.distance_m)),
            "{}",
            label.value
        );
    }
}

#[test]
fn live_records_the_sector_objects_of_every_scan_to_mcap() {
    let (_emulator, addr) = emulator();
    let dir = tmp_dir("live-sectors");
    let mcap_path = dir.join("run.mcap");
    let run = bin()
        .args(["live", &addr, "--scans", "25", "--sectors", "--record"])
        .arg(&mcap_path)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let stdout = String::from_utf8(run.stdout).unwrap();
    let printed: Vec<&str> = stdout.lines().filter(|l| l.starts_with("scan ")).collect();
    assert_eq!(printed.len(), 25, "{stdout}");

    let topics = mcap_topics(&std::fs::read(&mcap_path).unwrap());
    let (scans, lines, sectors) = (&topics["/scan"], &topics["/lines"], &topics["/sectors"]);
    assert_eq!((scans.len(), lines.len(), sectors.len()), (25, 25, 25));
    let mut objects_seen = 0;
    for k in 0..25 {
        assert_eq!(sectors[k].1, "foxglove.SceneUpdate");
        // Each scan's sectors at the scan's own time.
        assert_eq!(sectors[k].0, scans[k].0);
        assert_eq!(lines[k].0, scans[k].0);
        let objects = objects_of(&SceneUpdate::decode(lines[k].2.as_slice()).unwrap());
        let update = SceneUpdate::decode(sectors[k].2.as_slice()).unwrap();
        assert_scene_holds(&update, &objects);
        // What is printed is what is recorded.
        for s in Sector::ALL {
            let text = match objects.get(s) {
                Some(o) => format!("{}: distance {:.3} m", s.name(), o.distance_m),
                None => format!("{}: none", s.name()),
            };
            assert!(printed[k].contains(&text), "{} lacks {text}", printed[k]);
        }
        objects_seen += Sector::ALL
            .iter()
            .filter(|&&s| objects.get(s).is_some())
            .count();
    }
    // The maze's walls surround the sensor: most sectors hold an object.
    assert!(objects_seen >= 25, "{objects_seen} objects in 25 scans");
    let _ = std::fs::remove_dir_all(&dir);
}

fn read_ws(ws: &mut tungstenite::WebSocket<TcpStream>) -> Option<Message> {
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

/// Subscribes to every channel of the server on `port` and returns the schema and the first
/// message of `/sectors` and of `/lines` that carry the same log time.
fn watch_sectors(port: u16, start: Instant) -> (String, SceneUpdate, SceneUpdate) {
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
    let mut subscriptions: HashMap<u32, (String, String)> = HashMap::new();
    // Messages by topic and log time.
    let mut got: HashMap<(String, u64), Vec<u8>> = HashMap::new();
    loop {
        assert!(start.elapsed() < DEADLINE, "no /sectors with its /lines");
        match read_ws(&mut ws) {
            Some(Message::Text(t)) => {
                let v: serde_json::Value = serde_json::from_str(t.as_str()).unwrap();
                if v["op"] != "advertise" {
                    continue;
                }
                let mut subs = Vec::new();
                for c in v["channels"].as_array().unwrap() {
                    let sub = subscriptions.len() as u32 + 1;
                    let topic = c["topic"].as_str().unwrap().to_owned();
                    let schema = c["schemaName"].as_str().unwrap().to_owned();
                    subscriptions.insert(sub, (topic, schema));
                    subs.push(serde_json::json!({"id": sub, "channelId": c["id"]}));
                }
                let msg = serde_json::json!({"op": "subscribe", "subscriptions": subs});
                ws.send(Message::Text(msg.to_string().into())).unwrap();
            }
            Some(Message::Binary(b)) if b.len() >= 13 && b[0] == 1 => {
                let sub = u32::from_le_bytes(b[1..5].try_into().unwrap());
                let time = u64::from_le_bytes(b[5..13].try_into().unwrap());
                let Some((topic, _)) = subscriptions.get(&sub) else {
                    continue;
                };
                got.insert((topic.clone(), time), b[13..].to_vec());
                let (s, l) = (("/sectors".to_owned(), time), ("/lines".to_owned(), time));
                if let (Some(s), Some(l)) = (got.get(&s), got.get(&l)) {
                    let schema = subscriptions.values().find(|(t, _)| t == "/sectors");
                    let _ = ws.close(None);
                    return (
                        schema.unwrap().1.clone(),
                        SceneUpdate::decode(s.as_slice()).unwrap(),
                        SceneUpdate::decode(l.as_slice()).unwrap(),
                    );
                }
            }
            _ => {}
        }
    }
}

#[test]
fn live_serves_the_sector_objects_to_a_foxglove_viewer() {
    let start = Instant::now();
    let (_emulator, addr) = emulator();
    let mut live = Child(
        bin()
            .args(["live", &addr, "--view", "--port", "0", "--sectors"])
            .args(["--duration", "60"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let mut out = BufReader::new(live.0.stdout.take().unwrap());
    let mut first = String::new();
    out.read_line(&mut first).unwrap();
    // Keep reading what it prints (the sector lines), so that it never writes to a closed
    // pipe.
    std::thread::spawn(move || std::io::copy(&mut out, &mut std::io::sink()));
    let port = served_port(&first);
    let (schema, sectors, lines) = watch_sectors(port, start);
    assert_eq!(schema, "foxglove.SceneUpdate");
    assert_scene_holds(&sectors, &objects_of(&lines));
    assert_eq!(
        sectors.entities[0].timestamp, lines.entities[0].timestamp,
        "the sectors of the scan the lines came from"
    );
}

#[test]
fn names_it_cannot_write_and_a_bare_host_are_refused_before_any_sensor() {
    // Port 1 has no sensor: each error comes before the run would try to reach one.
    for (args, want) in [
        (
            &["127.0.0.1:1", "-o", "lines.txt"][..],
            "lines.txt: cannot write this name; expected lines JSONL",
        ),
        (
            &["127.0.0.1:1", "--record", "run.bin"],
            "run.bin: cannot write this name; expected an MCAP file named .mcap",
        ),
        (
            &["127.0.0.1:1", "--record", "run.mcap.gz"],
            "so .mcap.gz is read but not written",
        ),
        (
            &["localhost"],
            "localhost: no such serial device; a sensor on the network is HOST:PORT (e.g. \
             localhost:10940",
        ),
    ] {
        let o = bin().arg("live").args(args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!err.contains("Connection refused"), "{args:?}: {err}");
    }
}
