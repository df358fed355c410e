//! The driver against the emulator, over TCP and over a pseudo-terminal: start-up (also
//! from SCIP 1.1), every fault class, reconnection, accounting of every lost scan,
//! monotonic stamps, and the ranges read equal to the ranges served.
//!
//! Timeouts are generous and nothing asserts a speed: the machine may be busy.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::collections::HashMap;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use laserlines_hokuyo::emulator::{
    Emulator, EmulatorHandle, Faults, Model, ModelName, PatternFeed, Served, ServedFault, ServedLog,
};
use laserlines_hokuyo::{
    DriverError, DriverOptions, DropReason, Endpoint, HokuyoScan, NoReturn, ScanRequest, Scanner,
    ScannerOptions, Session, clock::HostClock, codec::Encoding,
};

fn start_tcp(model: ModelName, faults: Faults) -> (EmulatorHandle, Endpoint) {
    let e = Emulator::new(
        Model::new(model),
        Box::new(PatternFeed::new()),
        faults,
        ServedLog::in_memory(),
    )
    .serve_tcp("127.0.0.1:0")
    .expect("bind the emulator");
    let endpoint = e.local_addr().unwrap().to_string().parse().unwrap();
    (e, endpoint)
}

#[cfg(unix)]
fn start_pty(model: ModelName, faults: Faults) -> (EmulatorHandle, Endpoint) {
    let e = Emulator::new(
        Model::new(model),
        Box::new(PatternFeed::new()),
        faults,
        ServedLog::in_memory(),
    )
    .serve_pty()
    .expect("open a pseudo-terminal");
    let endpoint = Endpoint::Serial {
        path: e.pty_path().unwrap().to_owned(),
        baud: None,
    };
    (e, endpoint)
}

fn read(scanner: &mut Scanner, n: usize, limit: Duration) -> Vec<HokuyoScan> {
    let stop = AtomicBool::new(false);
    let start = Instant::now();
    let mut out = Vec::new();
    while out.len() < n {
        assert!(
            start.elapsed() < limit,
            "only {} of {n} scans within {limit:?}: {:?}",
            out.len(),
            scanner.stats()
        );
        out.push(scanner.next_scan(&stop).expect("a scan"));
    }
    out
}

/// Every scan delivered is one the emulator served, with the same readings (error codes
/// included); stamps and sensor times strictly increase; no time stamp twice.
fn check_delivered(scans: &[HokuyoScan], served: &[Served]) {
    let by_stamp: HashMap<(u32, &str), &Served> = served
        .iter()
        .map(|s| ((s.timestamp, &s.echo[..2]), s))
        .collect();
    let mut errors_seen = 0;
    for w in scans.windows(2) {
        assert!(
            w[1].scan.stamp.unwrap() > w[0].scan.stamp.unwrap(),
            "stamps must increase"
        );
        assert!(w[1].sensor_ms > w[0].sensor_ms, "no scan twice");
    }
    for s in scans {
        let served = by_stamp
            .values()
            .find(|v| v.timestamp == s.sensor_raw_ms && v.fault.is_none())
            .unwrap_or_else(|| panic!("scan at {} ms was not served whole", s.sensor_raw_ms));
        assert_eq!(
            s.raw_mm, served.values,
            "readings differ at {} ms",
            s.sensor_raw_ms
        );
        for (i, &mm) in s.raw_mm.iter().enumerate() {
            assert!((s.scan.ranges[i] - f64::from(mm) / 1000.0).abs() < 1e-12);
            if mm < 20 {
                errors_seen += 1;
                // An error code is never a valid range.
                assert!(s.scan.ranges[i] < s.scan.range_min);
            }
        }
    }
    assert!(errors_seen > 0, "the feed sends error codes; none was read");
}

/// The served scans up to the last one delivered, all accounted for: delivered, or
/// dropped with the reason matching the fault injected.
fn check_accounting(scanner: &Scanner, scans: &[HokuyoScan], served: &[Served]) {
    let last = scans.last().unwrap();
    let upto = served
        .iter()
        .position(|s| s.timestamp == last.sensor_raw_ms && s.fault.is_none())
        .expect("the last scan was served");
    let served = &served[..=upto];
    let count = |f: ServedFault| served.iter().filter(|s| s.fault == Some(f)).count() as u64;
    let d = scanner.stats().dropped;
    assert_eq!(
        d.get(DropReason::Checksum),
        count(ServedFault::Checksum),
        "{d}"
    );
    assert_eq!(
        d.get(DropReason::Truncated),
        count(ServedFault::Truncated) + count(ServedFault::Dropped),
        "{d}"
    );
    assert_eq!(d.get(DropReason::Gap), 0, "{d}");
    assert_eq!(d.get(DropReason::Duplicate), 0, "{d}");
    assert_eq!(
        scanner.stats().delivered + d.get(DropReason::Checksum) + d.get(DropReason::Truncated),
        served.len() as u64,
        "every served scan delivered or counted: {d}"
    );
}

#[test]
fn tcp_start_up_and_ranges_read_equal_ranges_served() {
    let (emulator, endpoint) = start_tcp(ModelName::Ust10lx, Faults::default());
    let mut scanner = Scanner::open(&endpoint, ScannerOptions::default()).unwrap();
    let info = scanner.info().clone();
    assert_eq!(info.model, "UST-10LX");
    assert_eq!(
        (info.amin, info.amax, info.afrt, info.ares),
        (0, 1080, 540, 1440)
    );
    assert!(!scanner.stats().switched_from_scip11);
    let scans = read(&mut scanner, 30, Duration::from_secs(30));
    let g = &scans[0].scan;
    assert_eq!(g.ranges.len(), 1081);
    assert!((g.angle_min.to_degrees() + 135.0).abs() < 1e-9);
    assert!((g.angle_max().to_degrees() - 135.0).abs() < 1e-9);
    assert_eq!((g.range_min, g.range_max), (0.02, 10.0));
    // The reasons of the readings below DMIN are kept.
    let reasons: Vec<NoReturn> = scans[0]
        .no_returns(info.dmin_mm, info.dmax_mm)
        .map(|(_, r)| r)
        .collect();
    assert!(!reasons.is_empty());
    check_delivered(&scans, &emulator.log().snapshot());
    check_accounting(&scanner, &scans, &emulator.log().snapshot());
    assert_eq!(scanner.stats().dropped.total(), 0);
    // The host stamp is no later than the arrival and close to it on a local link.
    let clock = scanner.stats().clock_offset_s.unwrap();
    assert!(clock.is_finite());
    scanner.close().unwrap();
    emulator.stop().unwrap();
}

#[test]
fn tcp_bad_checksums_and_cut_lines_are_dropped_and_counted() {
    let faults = Faults {
        bad_checksum_every: 5,
        truncate_every: 7,
        ..Faults::default()
    };
    let (emulator, endpoint) = start_tcp(ModelName::Ust10lx, faults);
    let mut scanner = Scanner::open(&endpoint, ScannerOptions::default()).unwrap();
    let scans = read(&mut scanner, 60, Duration::from_secs(60));
    let served = emulator.log().snapshot();
    check_delivered(&scans, &served);
    check_accounting(&scanner, &scans, &served);
    let d = scanner.stats().dropped;
    assert!(
        d.get(DropReason::Checksum) >= 10 && d.get(DropReason::Truncated) >= 6,
        "{d}"
    );
    scanner.close().unwrap();
    emulator.stop().unwrap();
}

#[test]
fn tcp_reconnects_within_two_seconds_of_the_sensor_coming_back() {
    let faults = Faults {
        drop_after: 15,
        down_for: Duration::from_millis(800),
        ..Faults::default()
    };
    let (emulator, endpoint) = start_tcp(ModelName::Ust10lx, faults);
    let mut scanner = Scanner::open(&endpoint, ScannerOptions::default()).unwrap();
    let stop = AtomicBool::new(false);
    let start = Instant::now();
    let mut scans = Vec::new();
    // Through two drops.
    while scanner.stats().reconnects < 2 || scans.len() < 40 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "{:?}",
            scanner.stats()
        );
        scans.push(scanner.next_scan(&stop).unwrap());
        let back = emulator.came_back();
        if let (Some(b), 1) = (back.first(), scanner.stats().reconnects) {
            // The first scan after the first return.
            let first_after = scans.last().unwrap().received;
            if first_after > *b {
                let waited = first_after - *b;
                assert!(
                    waited < Duration::from_secs(2),
                    "reconnected {waited:?} after the sensor came back"
                );
            }
        }
    }
    let served = emulator.log().snapshot();
    check_delivered(&scans, &served);
    check_accounting(&scanner, &scans, &served);
    let d = scanner.stats().dropped;
    assert!(d.get(DropReason::Disconnected) > 0, "{d}");
    // The half scans at each drop were counted as cut.
    assert!(d.get(DropReason::Truncated) >= 2, "{d}");
    scanner.close().unwrap();
    emulator.stop().unwrap();
}

#[test]
fn tcp_a_silent_sensor_is_reconnected() {
    let faults = Faults {
        stall_after: 10,
        stall_for: Duration::from_secs(3),
        ..Faults::default()
    };
    let (emulator, endpoint) = start_tcp(ModelName::Ust10lx, faults);
    let options = ScannerOptions {
        silence: Some(Duration::from_millis(600)),
        ..ScannerOptions::default()
    };
    let mut scanner = Scanner::open(&endpoint, options).unwrap();
    let scans = read(&mut scanner, 25, Duration::from_secs(60));
    assert!(scanner.stats().reconnects >= 1, "{:?}", scanner.stats());
    check_delivered(&scans, &emulator.log().snapshot());
    scanner.close().unwrap();
    emulator.stop().unwrap();
}

#[test]
fn tcp_slow_replies_and_a_wrapping_clock() {
    let faults = Faults {
        reply_delay: Duration::from_millis(100),
        clock_start_ms: (1 << 24) - 800,
        ..Faults::default()
    };
    let (emulator, endpoint) = start_tcp(ModelName::Ust10lx, faults);
    let mut scanner = Scanner::open(&endpoint, ScannerOptions::default()).unwrap();
    let scans = read(&mut scanner, 80, Duration::from_secs(60));
    assert!(
        scans.last().unwrap().sensor_ms >= 1 << 24,
        "the clock wrapped: {} ms",
        scans.last().unwrap().sensor_ms
    );
    assert!(scans.iter().any(|s| s.sensor_raw_ms < 10_000));
    check_delivered(&scans, &emulator.log().snapshot());
    check_accounting(&scanner, &scans, &emulator.log().snapshot());
    // Consecutive stamps one period apart across the wrap: 25 ms.
    for w in scans.windows(2) {
        assert_eq!(w[1].sensor_ms - w[0].sensor_ms, 25);
    }
    scanner.close().unwrap();
    emulator.stop().unwrap();
}

#[test]
fn tcp_single_scans_resets_and_statuses() {
    let (emulator, endpoint) = start_tcp(ModelName::Urg04lx, Faults::default());
    let mut s = Session::open(&endpoint, &DriverOptions::default(), HostClock::new()).unwrap();
    assert_eq!(s.info().dmax_mm, 5600);
    let gd = s.single_scan(s.info().full_request()).unwrap();
    assert_eq!(gd.raw_mm.len(), 682);
    let gs = ScanRequest {
        cluster: 3,
        encoding: Encoding::Two,
        ..ScanRequest::new(100, 400)
    };
    let clustered = s.single_scan(gs).unwrap();
    assert_eq!(clustered.raw_mm.len(), 101);
    let inc = std::f64::consts::TAU / 1024.0;
    assert!((clustered.scan.angle_min - (101.0 - 384.0) * inc).abs() < 1e-12);
    let served = emulator.log().snapshot();
    assert_eq!(served.len(), 2);
    assert_eq!(gd.raw_mm, served[0].values);
    assert_eq!(clustered.raw_mm, served[1].values);
    // A request beyond AMAX is refused with a status that says so.
    let bad = s.single_scan(ScanRequest::new(44, 800)).unwrap_err();
    assert!(
        matches!(&bad, DriverError::Status { source, .. } if source.meaning == "end step is out of range"),
        "{bad}"
    );
    // RT restarts the sensor clock: time is synchronised again and scans go on.
    s.reset(true).unwrap();
    s.reset(false).unwrap();
    let after = s.single_scan(s.info().full_request()).unwrap();
    assert!(after.sensor_raw_ms < 60_000);
    s.stop().unwrap();
    emulator.stop().unwrap();
}

#[cfg(unix)]
#[test]
fn pty_start_up_from_scip11_and_faults() {
    let faults = Faults {
        start_in_scip11: true,
        bad_checksum_every: 4,
        truncate_every: 6,
        ..Faults::default()
    };
    let (emulator, endpoint) = start_pty(ModelName::Urg04lx, faults);
    let mut scanner = Scanner::open(&endpoint, ScannerOptions::default()).unwrap();
    assert!(scanner.stats().switched_from_scip11);
    assert_eq!(scanner.info().model, "URG-04LX(Hokuyo Automatic Co., Ltd.)");
    let scans = read(&mut scanner, 20, Duration::from_secs(60));
    assert_eq!(scans[0].scan.ranges.len(), 682);
    let served = emulator.log().snapshot();
    check_delivered(&scans, &served);
    check_accounting(&scanner, &scans, &served);
    let d = scanner.stats().dropped;
    assert!(
        d.get(DropReason::Checksum) >= 4 && d.get(DropReason::Truncated) >= 2,
        "{d}"
    );
    scanner.close().unwrap();
    emulator.stop().unwrap();
}

#[cfg(unix)]
#[test]
fn pty_slow_replies_and_single_scans() {
    let faults = Faults {
        reply_delay: Duration::from_millis(50),
        ..Faults::default()
    };
    let (emulator, endpoint) = start_pty(ModelName::Urg04lx, faults);
    let mut s = Session::open(&endpoint, &DriverOptions::default(), HostClock::new()).unwrap();
    let gd = s.single_scan(s.info().full_request()).unwrap();
    assert_eq!(gd.raw_mm, emulator.log().snapshot()[0].values);
    s.stop().unwrap();
    emulator.stop().unwrap();
}

#[test]
fn nothing_listening_is_an_error_naming_the_endpoint() {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap();
    drop(listener);
    let endpoint: Endpoint = addr.to_string().parse().unwrap();
    let e = Scanner::open(&endpoint, ScannerOptions::default()).unwrap_err();
    assert!(e.to_string().starts_with(&addr.to_string()), "{e}");
    let e = Scanner::open(
        &Endpoint::Serial {
            path: "/dev/no-such-hokuyo".to_owned(),
            baud: None,
        },
        ScannerOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("/dev/no-such-hokuyo"), "{e}");
}
