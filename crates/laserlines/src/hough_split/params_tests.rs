//! Tests of [`HoughSplitParams`]: validation, the presets, the breakpoint distance, the bridge
//! and the criterion.
use super::*;

#[test]
fn defaults_and_paper_validate() {
    assert_eq!(HoughSplitParams::default().validate(), Ok(()));
    assert_eq!(HoughSplitParams::paper().validate(), Ok(()));
}

#[test]
fn scan_matching_caps_the_limit_on_r() {
    let m = HoughSplitParams::mapping();
    assert_eq!(m.max_r_sd, HoughSplitParams::MAPPING_MAX_R_SD);
    assert!(HoughSplitParams::default().max_r_sd > m.max_r_sd);
    assert!(!m.share_fits && !m.noise_along_beams);
    // Scan matching and a robot among obstacles keep glancing streaks; the defaults do not.
    assert_eq!(m.min_advance_t, 0.0);
    assert_eq!(HoughSplitParams::navigation().min_advance_t, 0.0);
    assert!(HoughSplitParams::default().min_advance_t > 0.0);
    // So do round obstacles' chords.
    assert_eq!(m.arc_significance, 0.0);
    assert_eq!(HoughSplitParams::navigation().arc_significance, 0.0);
    assert_eq!(HoughSplitParams::paper().arc_significance, 0.0);
    assert!(HoughSplitParams::default().arc_significance > 0.0);
    // Excursions stay in their pieces for scan matching and the paper, whatever a params
    // file says.
    assert!(!m.cut_excursions && !HoughSplitParams::paper().cut_excursions);
    assert!(HoughSplitParams::default().cut_excursions);
    assert!(HoughSplitParams::navigation().cut_excursions);
    assert!(!HoughSplitParams::complete().for_mapping().cut_excursions);
    assert!(!m.own_scatter && !HoughSplitParams::paper().own_scatter);
    assert!(HoughSplitParams::default().own_scatter && HoughSplitParams::navigation().own_scatter);
    assert!(!HoughSplitParams::complete().for_mapping().own_scatter);
    assert!(!m.local_bridge && !HoughSplitParams::paper().local_bridge);
    assert!(HoughSplitParams::default().local_bridge);
    // Bows split for scan matching, the paper and navigation; the defaults merge them, and
    // keep a piece within the split's bounds where its refined ends give no line.
    assert_eq!(m.min_bend, 0.0);
    assert_eq!(HoughSplitParams::paper().min_bend, 0.0);
    assert_eq!(HoughSplitParams::navigation().min_bend, 0.0);
    assert!(HoughSplitParams::default().min_bend > 0.0);
    assert!(HoughSplitParams::default().split_steps && HoughSplitParams::complete().split_steps);
    assert!(!m.split_steps && !HoughSplitParams::navigation().split_steps);
    assert!(!HoughSplitParams::paper().split_steps);
    assert!(!m.keep_split_bounds && !HoughSplitParams::paper().keep_split_bounds);
    assert!(!HoughSplitParams::navigation().keep_split_bounds);
    assert!(HoughSplitParams::default().keep_split_bounds);
    let loose = HoughSplitParams::complete().for_mapping();
    assert_eq!(loose.max_r_sd, HoughSplitParams::MAPPING_MAX_R_SD);
    let tight = HoughSplitParams {
        max_r_sd: 0.02,
        ..HoughSplitParams::default()
    };
    assert_eq!(tight.for_mapping().max_r_sd, 0.02);
    let nan = HoughSplitParams {
        max_r_sd: f64::NAN,
        ..HoughSplitParams::default()
    };
    assert!(nan.for_mapping().validate().is_err());
}

#[test]
fn bad_fields_are_named() {
    let p = HoughSplitParams {
        split_sigmas: 0.0,
        ..HoughSplitParams::default()
    };
    assert!(matches!(
        p.validate(),
        Err(ParamsError::NotPositive {
            field: "split_sigmas",
            ..
        })
    ));
    let p = HoughSplitParams {
        noise: NoiseModel::Fixed(crate::noise::RangeNoise::new(-1.0, 0.0)),
        ..HoughSplitParams::default()
    };
    assert!(matches!(
        p.validate(),
        Err(ParamsError::Negative {
            field: "noise.sigma_min",
            ..
        })
    ));
    type Setter = fn(&mut HoughSplitParams, f64);
    let fields: [(&str, Setter); 2] = [
        ("min_advance_t", |p, v| p.min_advance_t = v),
        ("arc_significance", |p, v| p.arc_significance = v),
    ];
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        for (name, set) in fields {
            let mut p = HoughSplitParams::default();
            set(&mut p, bad);
            assert!(
                matches!(p.validate(), Err(ParamsError::Negative { field, .. }) if field == name),
                "{name} = {bad}"
            );
        }
    }
}

#[test]
fn grids_that_would_exhaust_memory_and_empty_range_limits_are_refused() {
    let with = |f: fn(&mut HoughSplitParams)| {
        let mut p = HoughSplitParams::default();
        f(&mut p);
        p.validate().map_err(|e| e.to_string())
    };
    let e = with(|p| p.ring_step = 1e-8).unwrap_err();
    assert!(
        e.starts_with("ring_step must be finite and >= 0.0001"),
        "{e}"
    );
    let e = with(|p| p.ring_step = 1e-300).unwrap_err();
    assert_eq!(e, "ring_step must be finite and >= 0.0001, got 1e-300");
    let e = with(|p| p.ring_step = 1e300).unwrap_err();
    assert_eq!(e, "ring_step must be at most 100 (100 m), got 1e300");
    let e = with(|p| p.window = 1e6).unwrap_err();
    assert!(
        e.starts_with("window must be at most 1.92 (64 ring_step)"),
        "{e}"
    );
    let e = with(|p| p.bridge_incidence = 1e300).unwrap_err();
    assert_eq!(
        e,
        "bridge_incidence must be at most 1.5707 (90 deg), got 1e300"
    );
    let e = with(|p| p.sector_step = 10.0).unwrap_err();
    assert!(e.starts_with("sector_step must lie in (0, 6.28"), "{e}");
    let e = with(|p| p.range_limits = Some(RangeWindow::new(3.0, 0.03))).unwrap_err();
    assert!(e.starts_with("range_limits[1] must be above"), "{e}");
    // The edges themselves pass.
    let finest = |p: &mut HoughSplitParams| {
        p.ring_step = MIN_RING_STEP;
        p.window = MIN_RING_STEP / 2.0;
    };
    assert_eq!(with(finest), Ok(()));
    assert_eq!(with(|p| p.window = 64.0 * p.ring_step), Ok(()));
    assert_eq!(
        with(|p| {
            p.ring_step = MAX_RING_STEP;
            p.window = MAX_RING_STEP / 2.0;
        }),
        Ok(())
    );
}

#[test]
fn breakpoint_distance_grows_with_range_and_gap_and_stops_at_lambda() {
    let p = HoughSplitParams::default();
    let inc = 0.36f64.to_radians();
    let d1 = p.breakpoint_distance(2.0, inc, inc, 0.0).unwrap();
    // A surface at exactly lambda to the beams: points r sin(dphi) / sin(lambda - dphi)
    // apart.
    assert!((d1 - 2.0 * inc.sin() / (4f64.to_radians() - inc).sin()).abs() < 1e-12);
    assert!(p.breakpoint_distance(4.0, inc, inc, 0.0).unwrap() > d1);
    assert!(p.breakpoint_distance(2.0, 3.0 * inc, inc, 0.0).unwrap() > d1);
    let with_noise = p.breakpoint_distance(2.0, inc, inc, 0.01).unwrap();
    assert!((with_noise - d1 - 3.0 * 2f64.sqrt() * 0.01).abs() < 1e-12);
    // Never beyond lambda / 3, where D would reach r / 2.
    let at_limit = p
        .breakpoint_distance(2.0, 4f64.to_radians() / 3.0, inc, 0.0)
        .unwrap();
    assert!((at_limit - 1.0).abs() < 0.01, "{at_limit}");
    assert!(
        p.breakpoint_distance(2.0, 1.5f64.to_radians(), inc, 0.0)
            .is_none()
    );
    assert!(p.breakpoint_distance(2.0, f64::NAN, inc, 0.0).is_none());
    // A 1 deg scanner: lambda is raised to 10 deg.
    let deg = 1f64.to_radians();
    let coarse = p.breakpoint_distance(2.0, deg, deg, 0.0).unwrap();
    assert!((coarse - 2.0 * deg.sin() / 9f64.to_radians().sin()).abs() < 1e-12);
}

#[test]
fn sparse_scans_get_a_wider_bridge() {
    let p = HoughSplitParams::default();
    let urg = 360f64.to_radians() / 1024.0;
    // A few dropouts (up to 12 % on a URG-04LX): the dense scan's bridge.
    for dropout in [0.0, 0.05, 0.12, f64::NAN, -1.0] {
        let b = p.bridge_for(urg, dropout);
        assert_eq!(b.max_gap, 2, "{dropout}");
        let lambda_of = |step: f64| p.bridge_incidence.max(10.0 * step);
        assert_eq!(lambda_of(b.spacing), p.bridge_incidence, "{dropout}");
    }
    assert_eq!(p.bridge_for(urg, 0.2).max_gap, 2);
    // Half the beams missing: 0.5^7 < 1 % (6 missing beams), returns twice as far apart.
    let b = p.bridge_for(urg, 0.5);
    assert_eq!(b.max_gap, 6);
    assert!((b.spacing - 2.0 * urg).abs() < 1e-15);
    // Beyond 95 %, read as 95 %; never more than `MAX_BRIDGE_GAP`.
    assert_eq!(p.bridge_for(urg, 0.99), p.bridge_for(urg, 0.95));
    assert_eq!(p.bridge_for(urg, 0.95).max_gap, MAX_BRIDGE_GAP);
    // `D` never joins beyond `lambda / 3`, with `lambda` at most 60 deg: 20 deg.
    let step = 0.85f64.to_radians();
    let wide = p.bridge_for(step, 0.95);
    assert!(
        p.breakpoint_distance(1.0, 20f64.to_radians(), wide.spacing, 0.0)
            .is_some()
    );
    assert!(
        p.breakpoint_distance(1.0, 20.1f64.to_radians(), wide.spacing, 0.0)
            .is_none()
    );
}

#[test]
fn the_criterion_holds_for_the_papers_sectors() {
    let p = HoughSplitParams::default();
    // The URG-04LX (7.03 beams a sector) and finer scanners: as stated.
    assert_eq!(p.criterion_for(360f64.to_radians() / 1024.0), p.criterion);
    assert_eq!(p.criterion_for(-0.25f64.to_radians()), p.criterion);
    // A 1 deg scanner: 2.47 beams a sector, the criterion scaled by 2.47 / 7.03.
    let got = p.criterion_for(1f64.to_radians());
    assert!(
        (got - 0.5 * 2.47 / PAPER_SECTOR_BEAMS).abs() < 1e-9,
        "{got}"
    );
}

#[test]
fn sparse_scans_need_fewer_points() {
    let p = HoughSplitParams::default();
    let both = |n| MinPoints {
        segment: n,
        line: n,
    };
    // Dense scans, and the rates the URG-04LX's open space gives: the counts as they are.
    for dropout in [0.0, 0.05, 0.19, f64::NAN, -1.0] {
        assert_eq!(p.min_points_for(dropout), both(8), "{dropout}");
    }
    // 8 beams of which 80 % return: ceil(6.4) points; of which 70 %: ceil(5.6).
    assert_eq!(p.min_points_for(0.2), both(7));
    assert_eq!(p.min_points_for(0.3), both(6));
    assert_eq!(p.min_points_for(0.4), both(MIN_SPARSE_POINTS));
    // Never fewer than `MIN_SPARSE_POINTS`, never more than asked for.
    assert_eq!(p.min_points_for(0.9), both(MIN_SPARSE_POINTS));
    assert_eq!(p.min_points_for(f64::INFINITY), both(MIN_SPARSE_POINTS));
    let paper = HoughSplitParams::paper();
    assert_eq!(paper.min_points_for(0.9), both(3));
    let mixed = HoughSplitParams {
        min_segment_points: 10,
        min_line_points: 5,
        ..p
    };
    assert_eq!(
        mixed.min_points_for(0.25),
        MinPoints {
            segment: 8,
            line: 5
        }
    );
}
