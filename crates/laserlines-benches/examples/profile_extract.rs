//! Runs `hough-split` on the standard bench scan many times, for a profiler:
//! `valgrind --tool=callgrind target/release/examples/profile_extract 1000`.

use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000);
    let scan = laserlines_benches::bench_scan();
    let Ok(mut hs) = HoughSplit::new(HoughSplitParams::default()) else {
        return;
    };
    let mut lines = Vec::new();
    let mut total = 0;
    for _ in 0..n {
        hs.extract_into(std::hint::black_box(&scan), &mut lines);
        total += lines.len();
    }
    println!("{total} lines");
}
