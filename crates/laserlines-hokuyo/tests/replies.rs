//! Reply streams written independently of the crate (`tests/fixtures/`, see its README):
//! a URG-04LX start-up, `MD` scans of the whole area and a clustered `GS` scan, framed,
//! parsed and decoded to the values the fixtures were written with. And the inputs the
//! `hokuyo_reply` fuzz target's invariants caught (`tests/fixtures/regressions/`).

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::path::PathBuf;

use laserlines_hokuyo::codec::Encoding;
use laserlines_hokuyo::info::InfoError;
use laserlines_hokuyo::reply::{Framer, Reply, Status};
use laserlines_hokuyo::{NoReturn, ScanRequest, SensorInfo};

fn fixture(name: &str) -> Vec<u8> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The messages of a stream, pushed to the framer in pieces of `piece` bytes.
fn messages(bytes: &[u8], piece: usize) -> Vec<Vec<u8>> {
    let mut framer = Framer::new();
    let mut out = Vec::new();
    for chunk in bytes.chunks(piece) {
        framer.push(chunk);
        while let Some(m) = framer.next_message() {
            out.push(m);
        }
    }
    assert_eq!(framer.pending(), 0, "bytes left after the last message");
    out
}

fn echo(m: &[u8]) -> String {
    String::from_utf8_lossy(Reply::parse_unchecked(m).unwrap().echo).into_owned()
}

fn urg04lx_info() -> SensorInfo {
    let start = messages(&fixture("urg04lx-startup.scip"), 7);
    let info = |k: usize| Reply::parse_unchecked(&start[k]).unwrap().info().unwrap();
    SensorInfo::from_pairs(&info(1), &info(2), &info(3)).unwrap()
}

/// The reading of beam `k` of scan `j` in `urg04lx-md-scans.scip`.
fn md_reading(k: u32, j: u32) -> u32 {
    if k.is_multiple_of(50) {
        k % 20
    } else {
        20 + (37 * k + 11 * j) % 5581
    }
}

#[test]
fn a_urg04lx_start_up_gives_the_sensor_description_and_the_time() {
    let start = messages(&fixture("urg04lx-startup.scip"), 7);
    let echoes: Vec<String> = start.iter().map(|m| echo(m)).collect();
    assert_eq!(
        echoes,
        ["QT", "VV", "PP", "II", "TM0", "TM1", "TM2", "BM"].map(String::from)
    );
    // Every reply is status 00 with a verified check character; the data lines of the
    // others verify as plain lines, those of VV, PP and II as `LABEL:VALUE;C` lines.
    for (k, m) in start.iter().enumerate() {
        if (1..=3).contains(&k) {
            let r = Reply::parse_unchecked(m).unwrap();
            assert!(r.status.is_ok() && r.info().is_ok(), "{}", echoes[k]);
        } else {
            assert!(Reply::parse(m).unwrap().status.is_ok(), "{}", echoes[k]);
        }
    }
    let info = urg04lx_info();
    assert_eq!(info.product, "SOKUIKI Sensor URG-04LX");
    assert_eq!(info.serial, "H0000000");
    assert_eq!(info.protocol, "SCIP 2.0");
    assert_eq!(info.model, "URG-04LX(Hokuyo Automatic Co.,Ltd.)");
    assert_eq!((info.dmin_mm, info.dmax_mm), (20, 5600));
    assert_eq!(
        (info.ares, info.amin, info.amax, info.afrt),
        (1024, 44, 725, 384)
    );
    assert_eq!(info.scan_rpm, 600);
    assert_eq!(info.state.len(), 7);
    assert_eq!(info.state[1], ("LASR".to_owned(), "OFF".to_owned()));
    // TM1: the sensor's clock, 16,000,000 ms ("m2@0", the specification's example).
    let tm1 = Reply::parse(&start[5]).unwrap();
    assert_eq!(tm1.data_line(0), Some(&b"m2@0"[..]));
    assert_eq!(laserlines_hokuyo::codec::decode(b"m2@0"), Ok(16_000_000));
}

#[test]
fn md_scans_of_the_whole_area_decode_to_the_readings_written() {
    let info = urg04lx_info();
    let request = info.full_request();
    assert_eq!(request.stream_command(0), "MD0044072501000");
    let g = info.geometry(&request);
    assert_eq!(g.beams, 682);
    let stream = messages(&fixture("urg04lx-md-scans.scip"), 61);
    assert_eq!(stream.len(), 3);
    // The acknowledgement: status 00, no data.
    let ack = Reply::parse(&stream[0]).unwrap();
    assert!(ack.status.is_ok() && ack.data_line_count() == 0);
    let mut values = Vec::new();
    for (j, m) in stream[1..].iter().enumerate() {
        let r = Reply::parse_unchecked(m).unwrap();
        assert_eq!(r.status, Status::Scip2(*b"99"));
        r.check_scan_layout(Encoding::Three, 682).unwrap();
        r.verify_data().unwrap();
        // 682 values of 3 characters: 31 lines of 64 and one of 62, after the time stamp.
        assert_eq!(r.data_line_count(), 1 + 32);
        let stamp = r.scan_into(Encoding::Three, 682, &mut values).unwrap();
        assert_eq!(stamp, 16_000_100 + 100 * j as u32);
        let expected: Vec<u32> = (0..682).map(|k| md_reading(k, j as u32)).collect();
        assert_eq!(values, expected);
        // Every 50th beam is an error code, with its reason.
        assert_eq!(
            NoReturn::classify(values[0], info.dmin_mm, info.dmax_mm),
            Some(NoReturn::PossiblyFar)
        );
        assert_eq!(
            NoReturn::classify(values[350], info.dmin_mm, info.dmax_mm),
            Some(NoReturn::Other(10))
        );
        assert_eq!(
            NoReturn::classify(values[1], info.dmin_mm, info.dmax_mm),
            None
        );
    }
}

#[test]
fn a_clustered_gs_scan_decodes_with_two_characters() {
    let info = urg04lx_info();
    let request = ScanRequest {
        cluster: 2,
        encoding: Encoding::Two,
        ..ScanRequest::new(100, 109)
    };
    assert_eq!(request.single_command(), "GS0100010902");
    assert_eq!(request.values(), 5);
    let m = fixture("urg04lx-gs-cluster.scip");
    let r = Reply::parse(&m).unwrap();
    assert_eq!(r.echo, b"GS0100010902");
    assert!(r.status.is_ok());
    let mut values = Vec::new();
    assert_eq!(r.scan_into(Encoding::Two, 5, &mut values), Ok(123));
    assert_eq!(values, [4095, 0, 1234, 7, 20]);
    // Beams point at the middle of their two steps: 100.5, 102.5, ...
    let g = info.geometry(&request);
    let step = std::f64::consts::TAU / 1024.0;
    assert!((g.angle_min - (100.5 - 384.0) * step).abs() < 1e-12);
    assert!((g.angle_increment - 2.0 * step).abs() < 1e-15);
}

/// A `PP` reply naming steps beyond 9999 parsed, and the driver asked for steps 0..9999
/// (its command has 4 digits per step) while building scans of 10001 beams: every scan
/// would have been dropped as cut short. With `ARES` and `AMAX` near 2^32, it built a
/// scan of four billion beams. Such a description is now refused, naming `AMAX`.
#[test]
fn steps_beyond_four_digits_are_refused() {
    for (name, amax) in [
        ("regressions/pp-amax-beyond-four-digits.scip", 10_000u64),
        ("regressions/pp-four-billion-steps.scip", 4_294_967_294),
    ] {
        let m = fixture(name);
        let pairs = Reply::parse_unchecked(&m).unwrap().info().unwrap();
        let e = SensorInfo::from_pairs(&[], &pairs, &[]).unwrap_err();
        assert!(
            matches!(&e, InfoError::Inconsistent(text) if text.contains(&format!("AMAX {amax}"))),
            "{name}: {e}"
        );
    }
    // The last step a command can name is still accepted.
    let mut pairs: Vec<(String, String)> = [
        ("DMIN", "20"),
        ("DMAX", "30000"),
        ("ARES", "20000"),
        ("AMIN", "0"),
        ("AMAX", "9999"),
        ("AFRT", "5000"),
        ("SCAN", "2400"),
    ]
    .iter()
    .map(|(k, v)| ((*k).to_owned(), (*v).to_owned()))
    .collect();
    let info = SensorInfo::from_pairs(&[], &pairs, &[]).unwrap();
    assert_eq!(info.full_request().stream_command(0), "MD0000999901000");
    assert_eq!(info.geometry(&info.full_request()).beams, 10_000);
    pairs[4].1 = "10000".to_owned();
    assert!(SensorInfo::from_pairs(&[], &pairs, &[]).is_err());
}
