//! Batch throughput on real logs: `laserlines extract` end to end (parse, extract, write) against
//! extraction alone on the same scans, both on every core.
//!
//! - `end_to_end`: the release binary run on the log file, writing lines JSONL to a temporary
//!   file (process start included);
//! - `extract_only`: the log's scans already in memory, extracted on a rayon pool of the same
//!   size with one extractor per thread, as `extract` does;
//! - `read_only`: parsing the log (one thread, as `extract`'s reader thread does).
//!
//! ```sh
//! cargo bench -p laserlines-cli --bench batch
//! ```
//!
//! Needs `../shared/data/real` (skipped with a notice when absent).

#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use laserlines::{Line, LineExtractor};
use laserlines_io::ScanRecord;
use rayon::prelude::*;

const LOGS: [&str; 2] = [
    "carmen-radish-corrected/intel-corrected.log.gz",
    "mit-csail-clf/mit-csail.clf.gz",
];

fn real(path: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/real")
        .join(path);
    if p.is_file() {
        Some(p)
    } else {
        eprintln!("notice: {} is absent; skipping its benchmark", p.display());
        None
    }
}

fn read_all(path: &Path) -> Vec<ScanRecord> {
    laserlines_io::open(path, None)
        .unwrap()
        .map(|r| r.unwrap())
        .collect()
}

fn batch(c: &mut Criterion) {
    let jobs = std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .unwrap();
    let out = std::env::temp_dir().join(format!("laserlines-bench-{}.jsonl", std::process::id()));
    for log in LOGS {
        let Some(path) = real(log) else { continue };
        let records = read_all(&path);
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let mut group = c.benchmark_group(format!("batch/{name}"));
        group.sample_size(10);
        group.measurement_time(Duration::from_secs(10));
        group.throughput(Throughput::Elements(records.len() as u64));

        group.bench_function("end_to_end", |b| {
            b.iter(|| {
                let status = Command::new(env!("CARGO_BIN_EXE_laserlines"))
                    .args(["extract", "-o"])
                    .arg(&out)
                    .arg(&path)
                    .stderr(std::process::Stdio::null())
                    .status()
                    .unwrap();
                assert!(status.success());
            });
        });

        let extractors: Vec<Mutex<Box<dyn LineExtractor + Send>>> = (0..jobs)
            .map(|_| Mutex::new(laserlines::extractors::by_name("hough-split").unwrap()))
            .collect();
        let mut slots: Vec<Vec<Line>> = vec![Vec::new(); records.len()];
        group.bench_function("extract_only", |b| {
            b.iter(|| {
                pool.install(|| {
                    records
                        .par_iter()
                        .zip(slots.par_iter_mut())
                        .with_min_len(4)
                        .for_each(|(record, lines)| {
                            let i = rayon::current_thread_index().unwrap_or(0) % jobs;
                            let mut e = extractors[i].lock().unwrap();
                            e.extract_into(&record.scan, lines);
                        });
                });
            });
        });

        group.bench_function("read_only", |b| {
            b.iter(|| read_all(&path).len());
        });
        group.finish();
    }
    let _ = std::fs::remove_file(out);
}

criterion_group!(benches, batch);
criterion_main!(benches);
