//! A [`BenchReport`] as a markdown table (for the terminal and the README) and as CSV.

use std::fmt::Write as _;

use crate::bench::{AlgorithmMetrics, BenchReport};

/// A time in microseconds with about three significant digits.
fn us(v: f64) -> String {
    if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    }
}

impl BenchReport {
    /// The results as markdown: the overall table, then one table by group (suite or file).
    #[must_use]
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let truth = self.overall.iter().all(|m| m.truth.is_some()) && !self.overall.is_empty();
        if truth {
            self.truth_tables(&mut s);
        } else {
            self.log_table(&mut s);
        }
        self.group_table(&mut s, truth);
        s
    }

    /// With ground truth: the overall table and the errors on the pieces every extractor
    /// found.
    fn truth_tables(&self, s: &mut String) {
        s.push_str(
            "| algorithm | TP rate | FP rate | of which on a wall | F1 | RMS dr [mm] | RMS dalpha [deg] | median end-point error [mm] | lines/scan | median us/scan | scans/s |\n",
        );
        s.push_str("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for m in &self.overall {
            let Some(t) = m.truth else { continue };
            let on_wall = if t.lines == 0 {
                0.0
            } else {
                t.on_wall_lines as f64 / t.lines as f64
            };
            let _ = writeln!(
                s,
                "| {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} | {:.3} | {:.1} | {:.1} | {} | {:.0} |",
                m.algorithm,
                t.true_positive_rate,
                t.false_positive_rate,
                on_wall,
                t.f1,
                t.rms_dr_m * 1e3,
                t.rms_dalpha_rad.to_degrees(),
                t.median_endpoint_error_m * 1e3,
                m.lines_per_scan,
                us(m.speed.median_us_per_scan),
                m.speed.scans_per_second,
            );
        }
        let common: Vec<_> = self
            .overall
            .iter()
            .filter_map(|m| m.common.map(|c| (m, c)))
            .collect();
        if let Some((_, c0)) = common.first() {
            let _ = write!(
                s,
                "\nErrors on the {} significant pieces that every extractor found:\n\n| algorithm | RMS dr [mm] | RMS dalpha [deg] | median end-point error [mm] | 90 % of end-point errors below [mm] |\n|---|---:|---:|---:|---:|\n",
                c0.pieces
            );
            for (m, c) in &common {
                let _ = writeln!(
                    s,
                    "| {} | {:.2} | {:.3} | {:.1} | {:.1} |",
                    m.algorithm,
                    c.rms_dr_m * 1e3,
                    c.rms_dalpha_rad.to_degrees(),
                    c.median_endpoint_error_m * 1e3,
                    c.p90_endpoint_error_m * 1e3
                );
            }
        }
    }

    /// Without ground truth (real logs): lines, explained points, residuals and speed.
    fn log_table(&self, s: &mut String) {
        s.push_str(
            "| algorithm | lines/scan | points explained | residual RMS [mm] | median us/scan | scans/s |\n",
        );
        s.push_str("|---|---:|---:|---:|---:|---:|\n");
        for m in &self.overall {
            let _ = writeln!(
                s,
                "| {} | {:.1} | {:.3} | {:.2} | {} | {:.0} |",
                m.algorithm,
                m.lines_per_scan,
                m.explained_fraction,
                m.residual_rms_m * 1e3,
                us(m.speed.median_us_per_scan),
                m.speed.scans_per_second,
            );
        }
    }

    /// One column per group (suite or input), when there are several.
    fn group_table(&self, s: &mut String, truth: bool) {
        let groups = self.groups();
        if groups.len() <= 1 {
            return;
        }
        s.push('\n');
        s.push_str(if truth {
            "TP rate / FP rate by suite:\n\n| algorithm |"
        } else {
            "lines per scan / points explained by input:\n\n| algorithm |"
        });
        for g in &groups {
            let _ = write!(s, " {g} |");
        }
        s.push_str("\n|---|");
        for _ in &groups {
            s.push_str("---:|");
        }
        s.push('\n');
        for m in &self.overall {
            let _ = write!(s, "| {} |", m.algorithm);
            for g in &groups {
                let cell = self
                    .by_group
                    .iter()
                    .find(|x| x.algorithm == m.algorithm && x.group == *g)
                    .map_or_else(String::new, |x| match x.truth {
                        Some(t) if truth => {
                            format!("{:.2} / {:.2}", t.true_positive_rate, t.false_positive_rate)
                        }
                        _ => format!("{:.1} / {:.2}", x.lines_per_scan, x.explained_fraction),
                    });
                let _ = write!(s, " {cell} |");
            }
            s.push('\n');
        }
    }

    /// The results as CSV with a header: one row per extractor over all scans (group `all`),
    /// then one per group and extractor. Ground-truth columns are empty without truth. Units:
    /// metres, radians, microseconds.
    #[must_use]
    pub fn to_csv(&self) -> String {
        let mut s = String::from(
            "group,algorithm,scans,lines,lines_per_scan,pieces,found,true_positive_rate,false_lines,false_positive_rate,on_wall_lines,f1,rms_dr_m,rms_dalpha_rad,median_endpoint_error_m,p90_endpoint_error_m,common_pieces,common_rms_dr_m,common_rms_dalpha_rad,common_median_endpoint_error_m,common_p90_endpoint_error_m,explained_fraction,residual_rms_m,median_us_per_scan,mean_us_per_scan,scans_per_second\n",
        );
        for m in self.overall.iter().chain(&self.by_group) {
            csv_row(&mut s, m);
        }
        s
    }
}

/// Quotes a CSV field when it needs it.
fn field(v: &str) -> String {
    if v.contains([',', '"', '\n']) {
        format!("\"{}\"", v.replace('"', "\"\""))
    } else {
        v.to_string()
    }
}

fn csv_row(s: &mut String, m: &AlgorithmMetrics) {
    let truth = m.truth.map_or_else(
        || ",,,,,,,,".to_string(),
        |t| {
            format!(
                "{},{},{},{},{},{},{},{},{}",
                t.pieces,
                t.found,
                t.true_positive_rate,
                t.false_lines,
                t.false_positive_rate,
                t.on_wall_lines,
                t.f1,
                t.rms_dr_m,
                t.rms_dalpha_rad
            )
        },
    );
    let endpoint = m.truth.map_or_else(
        || ",".to_string(),
        |t| format!("{},{}", t.median_endpoint_error_m, t.p90_endpoint_error_m),
    );
    let common = m.common.map_or_else(
        || ",,,,".to_string(),
        |c| {
            format!(
                "{},{},{},{},{}",
                c.pieces,
                c.rms_dr_m,
                c.rms_dalpha_rad,
                c.median_endpoint_error_m,
                c.p90_endpoint_error_m
            )
        },
    );
    let _ = writeln!(
        s,
        "{},{},{},{},{},{},{},{},{},{},{},{},{}",
        field(&m.group),
        field(&m.algorithm),
        m.scans,
        m.lines,
        m.lines_per_scan,
        truth,
        endpoint,
        common,
        m.explained_fraction,
        m.residual_rms_m,
        m.speed.median_us_per_scan,
        m.speed.mean_us_per_scan,
        m.speed.scans_per_second
    );
}
