//! Prints every line `hough-split` (default parameters) extracts from a fixed set of scans,
//! with the bits of every float, so that two builds can be compared for identical output:
//! the scene suites of every simulated sensor (`all`, seed 2, 30 scans per suite or
//! `DUMP_SCANS`), the bundled real URG-04LX excerpt and, when it is there, the Intel Research
//! Lab log from `../shared`, and any logs named as arguments. With `DUMP_STAGES=1` also each
//! scan's data segments, removed beams, split points and noise estimate; with
//! `DUMP_PARAMS=paper`, `complete` or `navigation` the extractor has that preset instead of
//! the defaults.
//!
//! ```sh
//! cargo run --release -p laserlines-benches --example dump_lines > before.txt
//! ```

use std::io::Write;
use std::path::Path;

use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor, Scan};
use laserlines_eval::workload::{SENSORS, sensor, suite_scans};

/// The shared real log, relative to the workspace root.
const INTEL: &str = "../shared/data/real/carmen-radish-corrected/intel-corrected.log.gz";

fn bits(v: f64) -> String {
    format!("{:016x}", v.to_bits())
}

fn write_lines(out: &mut impl Write, name: &str, lines: &[Line]) -> std::io::Result<()> {
    writeln!(out, "{name} {}", lines.len())?;
    for l in lines {
        let c = &l.covariance;
        writeln!(
            out,
            "  {} {} {} r {} a {} s {} {} e {} {} rms {} cov {} {} {} {}",
            l.first,
            l.last,
            l.points,
            bits(l.r),
            bits(l.alpha),
            bits(l.start.x),
            bits(l.start.y),
            bits(l.end.x),
            bits(l.end.y),
            bits(l.rms),
            bits(c[(0, 0)]),
            bits(c[(0, 1)]),
            bits(c[(1, 0)]),
            bits(c[(1, 1)]),
        )?;
    }
    Ok(())
}

fn run(
    hs: &mut HoughSplit,
    out: &mut impl Write,
    name: &str,
    scan: &Scan,
    lines: &mut Vec<Line>,
) -> std::io::Result<()> {
    hs.extract_into(scan, lines);
    write_lines(out, name, lines)?;
    if std::env::var("DUMP_STAGES").is_ok_and(|v| v == "1") {
        let st = hs.stages();
        let segs: Vec<String> = st
            .segments()
            .map(|s| format!("{}-{}:{}", s.first, s.last, s.points))
            .collect();
        writeln!(out, "  segments {}", segs.join(" "))?;
        let removed: Vec<String> = st.removed().iter().map(ToString::to_string).collect();
        writeln!(out, "  removed {}", removed.join(" "))?;
        let splits: Vec<String> = st.split_points().map(|s| format!("{s:?}")).collect();
        writeln!(out, "  splits {}", splits.join(" "))?;
        let n = st.noise();
        writeln!(out, "  noise {} {}", bits(n.sigma_min), bits(n.fraction))?;
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let params = match std::env::var("DUMP_PARAMS").as_deref() {
        Ok("paper") => HoughSplitParams::paper(),
        Ok("navigation") => HoughSplitParams::navigation(),
        Ok("complete") => HoughSplitParams::complete(),
        Ok(other) => {
            return Err(format!("DUMP_PARAMS: paper, complete or navigation, not {other}").into());
        }
        Err(_) => HoughSplitParams::default(),
    };
    let mut hs = HoughSplit::new(params)?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut lines = Vec::new();
    // Scans per suite: 30, or DUMP_SCANS.
    let count = std::env::var("DUMP_SCANS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(30);
    for name in SENSORS {
        let Some(s) = sensor(name) else { continue };
        for bs in suite_scans("all", 2, count, &s)? {
            run(
                &mut hs,
                &mut out,
                &format!("{name} {}", bs.name),
                &bs.scan,
                &mut lines,
            )?;
        }
    }
    for (k, rec) in laserlines_io::demo::urg04lx_excerpt()?.iter().enumerate() {
        run(
            &mut hs,
            &mut out,
            &format!("demo:{k}"),
            &rec.scan,
            &mut lines,
        )?;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let intel = root.join(INTEL);
    if intel.exists() {
        for (k, rec) in laserlines_io::open(&intel, None)?.enumerate() {
            run(
                &mut hs,
                &mut out,
                &format!("intel:{k}"),
                &rec?.scan,
                &mut lines,
            )?;
        }
    } else {
        eprintln!("{} not found: the Intel log is left out", intel.display());
    }
    // Any other logs named on the command line.
    for log in std::env::args().skip(1) {
        for (k, rec) in laserlines_io::open(Path::new(&log), None)?.enumerate() {
            run(
                &mut hs,
                &mut out,
                &format!("{log}:{k}"),
                &rec?.scan,
                &mut lines,
            )?;
        }
    }
    out.flush()?;
    Ok(())
}
