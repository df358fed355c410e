//! Runs `hough-split` many times on the standard bench scan, or on the bundled real URG-04LX
//! scans, for a profiler:
//!
//! ```sh
//! valgrind --tool=callgrind target/release/examples/profile_extract 1000        # bench scan
//! valgrind --tool=callgrind target/release/examples/profile_extract 100 real    # 100 x 40 scans
//! valgrind --tool=callgrind target/release/examples/profile_extract 10 LOG 1000  # 10 x a log's first 1000 scans
//! ```

use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1000);
    let scans = match args.next().as_deref() {
        Some("real") => laserlines_benches::real_scans(),
        Some(log) => {
            let most = args
                .next()
                .and_then(|s| s.parse().ok())
                .unwrap_or(usize::MAX);
            log_scans(log, most)
        }
        None => vec![laserlines_benches::bench_scan()],
    };
    let Ok(mut hs) = HoughSplit::new(HoughSplitParams::default()) else {
        return;
    };
    let mut lines = Vec::new();
    let mut total = 0;
    for _ in 0..n {
        for scan in &scans {
            hs.extract_into(std::hint::black_box(scan), &mut lines);
            total += lines.len();
        }
    }
    println!("{total} lines from {} scans", n * scans.len());
}

/// The first `most` scans of the log at `path`; exits on the first bad record.
fn log_scans(path: &str, most: usize) -> Vec<laserlines::Scan> {
    let reader = match laserlines_io::reader::open(std::path::Path::new(path), None) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let mut scans = Vec::new();
    for record in reader.take(most) {
        match record {
            Ok(r) => scans.push(r.scan),
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        }
    }
    scans
}
