//! `laserlines bench` end to end on tiny suites: the outputs exist and parse, the tuning
//! output feeds back as a params file, bad names are clean errors; and every algorithm is
//! selectable by `extract` and `render`.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::extractors::ALGORITHMS;

mod common;
use common::{bin, excerpt, fails_with, run, text, tmp};

#[test]
fn bench_on_a_tiny_suite_writes_table_json_csv_and_chart() {
    let dir = tmp("out-all");
    let o = run(bin()
        .args(["bench", "--suite", "all", "--scans", "1", "-o"])
        .arg(&dir));
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    for name in ALGORITHMS {
        assert!(
            stdout.contains(&format!("| {name} |")),
            "{name} missing:\n{stdout}"
        );
    }
    assert!(
        stdout.contains("| algorithm | TP rate | FP rate |"),
        "{stdout}"
    );
    assert!(
        stdout.contains("hough-split is") && stdout.contains("times faster than iterative-hough"),
        "{stdout}"
    );

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("results.json")).unwrap()).unwrap();
    assert_eq!(json["scans"], 7, "one scan of each of the seven suites");
    let overall = json["overall"].as_array().unwrap();
    assert_eq!(overall.len(), ALGORITHMS.len());
    for m in overall {
        let t = &m["truth"];
        let tp = t["true_positive_rate"].as_f64().unwrap();
        let fp = t["false_positive_rate"].as_f64().unwrap();
        assert!(
            (0.0..=1.0).contains(&tp) && (0.0..=1.0).contains(&fp),
            "{m}"
        );
        assert!(
            m["speed"]["median_us_per_scan"].as_f64().unwrap() > 0.0,
            "{m}"
        );
        assert!(m["common"]["pieces"].as_u64().is_some(), "{m}");
    }
    assert_eq!(
        json["by_group"].as_array().unwrap().len(),
        7 * ALGORITHMS.len()
    );
    assert!(
        json["hough_split_vs_iterative_hough"]["of_medians"]
            .as_f64()
            .unwrap()
            > 0.0
    );

    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows.len(),
        1 + 8 * ALGORITHMS.len(),
        "header, overall and 7 suites"
    );
    assert!(rows.iter().all(|r| r.len() == rows[0].len()), "ragged CSV");
    let col = rows[0]
        .iter()
        .position(|h| *h == "true_positive_rate")
        .unwrap();
    for r in &rows[1..] {
        let v: f64 = r[col].parse().unwrap();
        assert!((0.0..=1.0).contains(&v));
    }

    let svg = std::fs::read_to_string(dir.join("accuracy-speed.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") || svg.starts_with("<?xml"),
        "not an SVG"
    );
    assert_eq!(
        svg.matches("class=\"chart-label\"").count(),
        ALGORITHMS.len()
    );
}

#[test]
fn bench_on_a_real_log_reports_coverage() {
    let dir = tmp("out-data");
    let o = run(bin()
        .args([
            "bench",
            "--algorithms",
            "hough-split,iepf",
            "--scans",
            "5",
            "-o",
        ])
        .arg(&dir)
        .arg("--data")
        .arg(excerpt()));
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("points explained"), "{stdout}");
    assert!(stdout.contains("not measured"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("results.json")).unwrap()).unwrap();
    assert_eq!(json["scans"], 5);
    for m in json["overall"].as_array().unwrap() {
        assert!(m["truth"].is_null());
        let f = m["explained_fraction"].as_f64().unwrap();
        assert!(f > 0.5 && f <= 1.0, "{m}");
        assert!(m["lines_per_scan"].as_f64().unwrap() > 1.0);
    }
    assert!(dir.join("results.csv").exists() && dir.join("accuracy-speed.svg").exists());
}

#[test]
fn tuning_prints_a_params_table_that_bench_accepts() {
    // hough-split's knobs are flat keys; iepf's include nested ones (`breakpoints.noise`).
    for (name, key) in [
        ("hough-split", "criterion = "),
        ("iepf", "breakpoints.noise = "),
    ] {
        let o = run(bin().args(["bench", "--tune", name, "--suite", "rooms", "--scans", "2"]));
        assert!(o.status.success(), "{}", text(&o.stderr));
        let stdout = text(&o.stdout);
        assert!(stdout.contains(&format!("[{name}]")), "{stdout}");
        assert!(stdout.contains(key), "{stdout}");
        let params = tmp(&format!("tuned-{name}.toml"));
        std::fs::write(&params, &stdout).unwrap();
        let o = run(bin()
            .args([
                "bench",
                "--suite",
                "rooms",
                "--scans",
                "1",
                "--algorithms",
                name,
                "--params",
            ])
            .arg(&params)
            .arg("-o")
            .arg(tmp(&format!("out-tuned-{name}"))));
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
}

#[test]
fn a_preset_applies_to_the_extractors_that_have_it() {
    // `complete` keeps more lines on the same scans; iepf, without presets, the same.
    let lines = |extra: &[&str]| {
        let dir = tmp(&format!("out-preset-{}", extra.len()));
        let o = run(bin()
            .args([
                "bench",
                "--suite",
                "clutter",
                "--scans",
                "6",
                "--algorithms",
            ])
            .arg("hough-split,iepf")
            .args(extra)
            .arg("-o")
            .arg(&dir));
        assert!(o.status.success(), "{}", text(&o.stderr));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("results.json")).unwrap())
                .unwrap();
        let per_scan = |name: &str| {
            json["overall"]
                .as_array()
                .unwrap()
                .iter()
                .find(|m| m["algorithm"] == name)
                .map(|m| m["lines_per_scan"].as_f64().unwrap())
                .unwrap()
        };
        (per_scan("hough-split"), per_scan("iepf"))
    };
    let (plain, complete) = (lines(&[]), lines(&["--preset", "complete"]));
    assert!(complete.0 > plain.0, "{complete:?} against {plain:?}");
    assert_eq!(complete.1, plain.1);
    let o = run(bin().args(["bench", "--algorithms", "iepf", "--preset", "walls"]));
    fails_with(&o, &["--preset walls", "none of the extractors"]);
}

#[test]
fn unknown_algorithm_suite_and_sensor_are_clean_errors() {
    let out = tmp("out-bad");
    let o = run(bin()
        .args(["bench", "--algorithms", "hough-split,nope", "-o"])
        .arg(&out));
    fails_with(&o, &["unknown algorithm", "nope", "iterative-hough"]);
    let o = run(bin().args(["bench", "--suite", "moon", "-o"]).arg(&out));
    fails_with(&o, &["unknown scene suite", "moon", "rooms", "all, arenas"]);
    let o = run(bin()
        .args(["bench", "--sensor", "lidar9000", "-o"])
        .arg(&out));
    fails_with(&o, &["unknown sensor", "lidar9000"]);
    let o = run(bin().args(["bench", "--tune", "nope"]));
    fails_with(&o, &["unknown algorithm", "nope"]);
    let o = run(bin().arg("bench").arg("--data").arg(tmp("missing.dat")));
    fails_with(&o, &["missing.dat"]);
    // Options of the simulated suites are refused with real logs, not ignored.
    for option in [
        ["--sensor", "urg04lx-full"],
        ["--criteria", "field"],
        ["--seed", "3"],
    ] {
        let o = run(bin().arg("bench").args(option).arg("--data").arg(excerpt()));
        fails_with(&o, &[option[0], "cannot be used with"]);
    }
}

#[test]
fn extract_and_render_accept_every_algorithm() {
    let dat = excerpt();
    for name in ALGORITHMS {
        let o = run(bin().args(["extract", "--algorithm", name]).arg(&dat));
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        let first: serde_json::Value =
            serde_json::from_str(text(&o.stdout).lines().next().unwrap()).unwrap();
        assert!(!first["lines"].as_array().unwrap().is_empty(), "{name}");
    }
    let svg = tmp("ransac.svg");
    let o = run(bin()
        .args(["render", "--algorithm", "ransac", "-o"])
        .arg(&svg)
        .arg(&dat));
    assert!(o.status.success(), "{}", text(&o.stderr));
    // A params table for another algorithm changes its result.
    let params = tmp("iepf.toml");
    std::fs::write(&params, "[iepf]\nfilter.min_length = 1.5\n").unwrap();
    let plain = run(bin().args(["extract", "--algorithm", "iepf"]).arg(&dat));
    let strict = run(bin()
        .args(["extract", "--algorithm", "iepf", "--params"])
        .arg(&params)
        .arg(&dat));
    assert!(strict.status.success(), "{}", text(&strict.stderr));
    assert_ne!(plain.stdout, strict.stdout);
    std::fs::write(&params, "[iepf]\nsplit_distanc = 0.02\n").unwrap();
    let o = run(bin()
        .args(["extract", "--algorithm", "iepf", "--params"])
        .arg(&params)
        .arg(&dat));
    fails_with(&o, &["iepf.toml", "split_distanc"]);
}
