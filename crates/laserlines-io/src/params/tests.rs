//! Tests of params files: tables over defaults and presets, errors naming file, table and key.

use super::*;
use laserlines::extractors::SplitMergeParams;
use laserlines::{HoughSplitParams, RangeWindow, Weight};

fn file(text: &str) -> ParamsFile {
    ParamsFile::parse(text, "p.toml").unwrap()
}

fn error(text: &str, algorithm: &str) -> String {
    match ParamsFile::parse(text, "p.toml") {
        Ok(f) => f.extractor(algorithm).err().unwrap().to_string(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn hough_split_noise_is_auto_a_preset_or_a_model() {
    use laserlines::{NoiseModel, RangeNoise};
    let p = |text: &str| file(text).algorithm_params(&registry::HOUGH_SPLIT);
    assert_eq!(p("").unwrap().noise, NoiseModel::Auto);
    assert_eq!(
        p("[hough-split]\nnoise = \"ydlidar-x4\"\n").unwrap().noise,
        NoiseModel::Fixed(RangeNoise::preset("ydlidar-x4").unwrap())
    );
    assert_eq!(
        p("[hough-split]\nnoise = { sigma_min = 0.004, fraction = 0.002 }\n")
            .unwrap()
            .noise,
        NoiseModel::Fixed(RangeNoise::new(0.004, 0.002))
    );
    assert_eq!(
        p("[hough-split]\nnoise = \"auto\"\n").unwrap().noise,
        NoiseModel::Auto
    );
    let e = p("[hough-split]\nnoise = \"cheap\"\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("unknown noise \"cheap\"") && e.contains("urg-04lx"),
        "{e}"
    );
    let e = p("[hough-split]\nnoise = { sigma_min = -0.01, fraction = 0.0 }\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("noise.sigma_min"), "{e}");
}

#[test]
fn a_preset_by_option_replaces_the_tables_preset_and_keeps_its_keys() {
    let none = ParamsFile::default()
        .with_preset("hough-split", "complete")
        .unwrap();
    assert_eq!(
        none.algorithm_params(&registry::HOUGH_SPLIT).unwrap(),
        HoughSplitParams::complete()
    );
    assert_ne!(HoughSplitParams::complete(), HoughSplitParams::default());
    let f = file("[hough-split]\npaper = true\nmin_range = 0.3\n")
        .with_preset("hough-split", "complete")
        .unwrap();
    let p = f.algorithm_params(&registry::HOUGH_SPLIT).unwrap();
    assert_eq!(
        p,
        HoughSplitParams {
            min_range: 0.3,
            ..HoughSplitParams::complete()
        }
    );
    // The option replaces the table's preset whichever comes first in the registry.
    let f = file("[hough-split]\ncomplete = true\n")
        .with_preset("hough-split", "paper")
        .unwrap();
    assert_eq!(
        f.algorithm_params(&registry::HOUGH_SPLIT).unwrap(),
        HoughSplitParams::paper()
    );
    // A preset key of the wrong type stays an error.
    let f = file("[hough-split]\npaper = \"yes\"\n")
        .with_preset("hough-split", "walls")
        .unwrap();
    let e = f.algorithm_params(&registry::HOUGH_SPLIT).unwrap_err();
    assert_eq!(
        e.to_string(),
        "p.toml: [hough-split] paper: expected true or false, found \"yes\""
    );
    let e = ParamsFile::default()
        .with_preset("hough-split", "wall")
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown preset \"wall\" of hough-split: expected one of paper, navigation, walls, complete"
    );
    let e = ParamsFile::default()
        .with_preset("iepf", "walls")
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown preset \"walls\" of iepf: expected none (it has no presets)"
    );
    assert!(matches!(
        ParamsFile::default().with_preset("nope", "walls"),
        Err(ParamsFileError::UnknownAlgorithm(_))
    ));
}

#[test]
fn two_presets_in_one_table_are_an_error_naming_both() {
    let e = error("[hough-split]\npaper = true\nwalls = true\n", "hough-split");
    assert_eq!(
        e,
        "p.toml: [hough-split] walls: a second preset: paper = true and walls = true; set at \
         most one preset to true"
    );
    // One preset true and another false is one preset.
    let f = file("[hough-split]\npaper = false\nwalls = true\n");
    assert_eq!(
        f.algorithm_params(&registry::HOUGH_SPLIT).unwrap(),
        HoughSplitParams::walls()
    );
}

#[test]
fn tables_lay_over_defaults_and_presets() {
    let f = file("[hough-split]\nring_step = 0.05\nweight = \"one\"\nrange_limits = [0.1, 2.0]\n");
    let p = f.algorithm_params(&registry::HOUGH_SPLIT).unwrap();
    assert_eq!(p.ring_step, 0.05);
    assert_eq!(p.weight, Weight::One);
    assert_eq!(p.range_limits, Some(RangeWindow::new(0.1, 2.0)));
    assert_eq!(p.criterion, HoughSplitParams::default().criterion);
    // No table: the defaults; the paper preset.
    let none = ParamsFile::default();
    assert_eq!(
        none.algorithm_params(&registry::HOUGH_SPLIT).unwrap(),
        HoughSplitParams::default()
    );
    let paper = file("[hough-split]\npaper = true\n");
    assert_eq!(
        paper.algorithm_params(&registry::HOUGH_SPLIT).unwrap(),
        HoughSplitParams::paper()
    );
    // iepf and split-and-merge start from their own defaults.
    let f = file("[iepf]\nsplit_distance = 0.02\n[split-and-merge]\nmin_cluster_points = 5\n");
    let iepf = f.algorithm_params(&registry::IEPF).unwrap();
    assert_eq!(iepf.split_distance, 0.02);
    assert_eq!(iepf.breakpoints.noise, 0.01);
    let sam = f.algorithm_params(&registry::SPLIT_AND_MERGE).unwrap();
    assert_eq!(sam.min_cluster_points, 5);
    assert_eq!(
        sam.breakpoints,
        SplitMergeParams::split_and_merge().breakpoints
    );
    // Nested keys, dotted or as a sub-table.
    let dotted = file("[iepf]\nbreakpoints.max_gap = 4\nfilter.min_length = 0.3\n");
    let table = file("[iepf.breakpoints]\nmax_gap = 4\n[iepf.filter]\nmin_length = 0.3\n");
    for f in [dotted, table] {
        let p = f.algorithm_params(&registry::IEPF).unwrap();
        assert_eq!((p.breakpoints.max_gap, p.filter.min_length), (4, 0.3));
        assert_eq!(p.breakpoints.incidence, 10f64.to_radians());
    }
}

#[test]
fn every_field_of_every_params_struct_is_a_key() {
    // The defaults written out as a table read back as the defaults.
    struct RoundTrip;
    impl Visitor for RoundTrip {
        type Output = ();
        fn visit<P: Params>(self, entry: &'static Algorithm<P>) {
            let start = (entry.defaults)();
            let mut tables = toml::Table::new();
            tables.insert(
                entry.name.to_owned(),
                toml::Value::Table(toml::Table::try_from(&start).unwrap()),
            );
            let text = toml::to_string(&tables).unwrap();
            let f = ParamsFile::parse(&text, "all.toml").unwrap();
            assert_eq!(f.algorithm_params(entry).unwrap(), start, "{text}");
            let bad = format!("[{}]\nno_such_key = 1\n", entry.name);
            let e = ParamsFile::parse(&bad, "bad.toml")
                .unwrap()
                .extractor(entry.name)
                .err()
                .unwrap()
                .to_string();
            assert!(e.contains("no_such_key") && e.contains(entry.name), "{e}");
        }
    }
    for name in registry::ALGORITHMS {
        registry::visit(name, RoundTrip);
    }
}

#[test]
fn errors_name_the_file_the_table_and_the_key() {
    assert_eq!(
        error("[em]\ninlier_probability = 2.0\n", "em"),
        "p.toml: [em] inlier_probability must lie in (0, 1), got 2"
    );
    assert_eq!(
        error("[hough-split]\nring_stp = 1.0\n", "hough-split"),
        "p.toml: [hough-split]: unknown field `ring_stp`, expected one of `ring_step`, \
         `sector_step`, `window`, `weight`, `criterion`, `group_gap`, `noise`, \
         `noise_floor`, `bridge_beams`, `bridge_incidence`, `bridge_sigmas`, \
         `bridge_max_gap`, `local_bridge`, `min_segment_points`, `split_sigmas`, \
         `split_significance`, `min_bend`, `split_steps`, \
         `noise_along_beams`, `merge_collinear`, `cut_excursions`, `keep_split_bounds`, \
         `share_fits`, \
         `refine_ends`, \
         `min_line_points`, \
         `min_line_length`, `max_rms_sigmas`, `min_advance_t`, `arc_significance`, \
         `max_alpha_sd`, `max_r_sd`, `own_scatter`, \
         `remove_mixed_pixels`, `min_range`, `range_limits`"
    );
    assert_eq!(
        error("[iepf]\nbreakpoints.noise = \"x\"\n", "iepf"),
        "p.toml: [iepf] breakpoints.noise: invalid type: string \"x\", expected f64"
    );
    assert_eq!(
        error("[iepf]\nbreakpoints.incidence = 2\n", "iepf"),
        "p.toml: [iepf] breakpoints.incidence must lie in (0, 1.5707963267948966), got 2"
    );
    assert_eq!(
        error("[hough-split]\nweight = \"square\"\n", "hough-split"),
        "p.toml: [hough-split] weight: unknown variant `square`, expected `one` or `range`"
    );
    assert_eq!(
        error("[hough-split]\npaper = 1\n", "hough-split"),
        "p.toml: [hough-split] paper: expected true or false, found 1"
    );
    assert!(error("[no-such-algorithm]\n", "iepf").starts_with("p.toml: unknown table"));
    assert!(error("[iepf\n", "iepf").starts_with("p.toml: invalid params file"));
    assert_eq!(
        ParamsFile::default()
            .extractor("nope")
            .err()
            .unwrap()
            .to_string(),
        "unknown algorithm \"nope\": expected one of hough-split, iterative-hough, \
         split-and-merge, iepf, incremental, line-regression, ransac, em"
    );
    // The tables of the simulator are accepted and left alone.
    let f = file("[robot]\nwhatever = 1\n[hough-split]\n");
    assert!(f.has("robot") && f.extractor("hough-split").is_ok());
}

#[test]
fn presets_round_trip_through_json_with_their_limits_off() {
    // JSON writes `inf` as `null`; the limits that `inf` turns off read it back as `inf`.
    for p in [
        HoughSplitParams::paper(),
        HoughSplitParams::complete(),
        HoughSplitParams::navigation(),
        HoughSplitParams::default(),
    ] {
        let text = serde_json::to_string(&p).unwrap();
        let back: HoughSplitParams = serde_json::from_str(&text).unwrap();
        assert_eq!(back, p, "{text}");
    }
    assert!(
        serde_json::to_string(&HoughSplitParams::paper())
            .unwrap()
            .contains("\"max_rms_sigmas\":null")
    );
}
