//! CSV files of readings at their own bearings (a spinning scanner's raw output): put on a
//! grid of beams, their left-out readings counted, their mistakes named.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::io::Cursor;

use laserlines_io::csv::SKIP_SHARED_BEAM;
use laserlines_io::{Format, ReadError, ScanRecord, from_reader};

fn read(text: &str) -> (Vec<Result<ScanRecord, ReadError>>, u64) {
    let mut reader = from_reader(
        "raw.csv",
        Cursor::new(text.as_bytes().to_vec()),
        Format::Csv,
    )
    .expect("opens");
    let items: Vec<_> = reader.by_ref().collect();
    let shared = reader.skipped().get(SKIP_SHARED_BEAM);
    (items, shared)
}

#[test]
fn clockwise_degrees_and_millimetres_make_a_counter_clockwise_scan_in_metres() {
    // A turn of 360 readings 1 deg apart, clockwise, out of order, two without a return (0),
    // and one more reading on the beam of 90 deg, farther than the one there.
    let mut rows = Vec::new();
    for k in (0..360).rev() {
        let range = if k == 17 || k == 200 { 0 } else { 1000 + k };
        rows.push(format!("{:.2},{range}", f64::from(k) + 0.1));
    }
    rows.push("90.3,5000".to_owned());
    let text = format!(
        "# clockwise: 1\n# range_min: 0.15\n# range_max: 12\n# stamp: 12.5\nangle_deg,range_mm\n{}\n",
        rows.join("\n")
    );
    let (items, shared) = read(&text);
    assert_eq!(items.len(), 1);
    let scan = &items[0].as_ref().unwrap().scan;
    assert_eq!(shared, 1);
    assert!(scan.full_turn());
    assert_eq!(scan.ranges.len(), 360);
    assert!((scan.angle_increment - 1f64.to_radians()).abs() < 1e-12);
    assert_eq!(scan.stamp, Some(12.5));
    assert_eq!((scan.range_min, scan.range_max), (0.15, 12.0));
    // Clockwise 90.1 deg is counter-clockwise -90.1 deg: the beam nearest -pi/2 holds 1.090 m,
    // the nearer of the two readings there.
    let at = |deg: f64| {
        let k = (deg.to_radians() - scan.angle_min) / scan.angle_increment;
        scan.ranges[k.round().rem_euclid(360.0) as usize]
    };
    assert!((at(-90.1) - 1.090).abs() < 1e-12, "{}", at(-90.1));
    assert!((at(-45.1) - 1.045).abs() < 1e-12, "{}", at(-45.1));
    assert_eq!(
        at(-17.1),
        0.0,
        "a reading of 0 is kept, below range_min: no return"
    );
}

#[test]
fn a_sector_of_radians_and_metres_starts_after_its_gap() {
    let rows: Vec<String> = (0..=200)
        .map(|i| {
            let b = -1.0 + f64::from(i) * 0.01;
            format!("{b},{}", 2.0 + f64::from(i) * 0.001)
        })
        .collect();
    let text = format!("angle_rad,range_m\n{}\n", rows.join("\n"));
    let (items, shared) = read(&text);
    let scan = &items[0].as_ref().unwrap().scan;
    assert_eq!(shared, 0);
    assert!((scan.angle_min + 1.0).abs() < 1e-12);
    assert!((scan.angle_increment - 0.01).abs() < 1e-12);
    assert_eq!(scan.ranges.len(), 201);
    assert_eq!(scan.ranges[200], 2.2);
}

#[test]
fn mistakes_in_a_file_of_readings_are_named() {
    let cases = [
        (
            "# angle_min: 0\nangle_rad,range_m\n0,1\n0.1,1\n",
            "raw.csv:1",
            "no `# angle_min:`",
        ),
        ("angle_rad,range_m\n0,1\nx,1\n", "raw.csv:3", "angle_rad"),
        (
            "angle_deg,range_mm\n0,1\n1,far\n",
            "raw.csv:3",
            "millimetres",
        ),
        (
            "angle_rad,range_m\n0,1,2\n",
            "raw.csv:2",
            "2 columns (angle_rad,range_m)",
        ),
        (
            "angle_rad,range_m\n",
            "raw.csv:2",
            "at least one row of readings",
        ),
        (
            "angle_rad,range_m\n0.5,1\n0.5,2\n",
            "raw.csv:1",
            "give angle_increment",
        ),
        (
            "angle,range\n0,1\n",
            "raw.csv:1",
            "`angle_rad,range_m` for readings",
        ),
    ];
    for (text, at, says) in cases {
        let (items, _) = read(text);
        let e = items[0].as_ref().unwrap_err().to_string();
        assert!(e.starts_with(at), "{text:?}: {e}");
        assert!(e.contains(says), "{text:?}: {e}");
    }
}
