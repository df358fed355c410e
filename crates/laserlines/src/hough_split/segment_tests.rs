//! Tests of step 4, the data segments.

use super::*;

/// Points of beams `0..ranges.len()` straight ahead (the beams 0.02 deg apart, so that
/// `D` is almost all noise term), all in cell 1, a component of its own.
fn cut(ranges: &[f64]) -> Vec<(u32, u32)> {
    let p = HoughSplitParams::default();
    let increment = 0.02f64.to_radians();
    let noise = RangeNoise::new(0.01, 0.0);
    let mut bp = Breakpoints::default();
    bp.prepare(&p, increment, noise, (0.0, 0.0, f64::INFINITY));
    let points: Vec<Pt> = ranges
        .iter()
        .enumerate()
        .map(|(idx, &range)| {
            let a = idx as f64 * increment;
            Pt {
                x: range * a.cos(),
                y: range * a.sin(),
                range,
                idx,
            }
        })
        .collect();
    let cell_of = vec![1; points.len()];
    let root_of = [NONE, 1];
    let input = RunInput {
        ranges,
        points: &points,
        cell_of: &cell_of,
        root_of: &root_of,
        bp: &bp,
        min: 1,
    };
    let mut kept = vec![Pt::default(); points.len()];
    let mut runs = Vec::new();
    let m = runs_of::<true>(&input, &mut kept, &mut runs);
    // Each run as its first and last beam.
    runs.iter()
        .map(|r| {
            let (a, b) = (r.start as usize, r.end as usize - 1);
            assert!(b < m);
            (kept[a].idx as u32, kept[b].idx as u32)
        })
        .collect()
}

/// 40 beams at 2 m; sigma is 1 cm, `D` about 4.3 cm.
fn flat() -> Vec<f64> {
    vec![2.0; 40]
}

#[test]
fn a_lone_jump_of_the_noise_does_not_cut_a_run() {
    // 4.5 sigma out, then back: the point goes, the run goes on.
    let mut r = flat();
    r[20] = 2.045;
    assert_eq!(cut(&r), [(0, 39)]);
    // The same on the other side, with the jump seen from the point after it: the
    // point before the jump joins it, the one after does not.
    let mut r = flat();
    r[19] = 2.0;
    r[20] = 2.04;
    r[21] = 1.995;
    assert_eq!(cut(&r), [(0, 39)]);
}

#[test]
fn a_point_well_off_the_run_or_a_step_still_cuts_it() {
    // 10 sigma in front: an edge, even when the run comes back behind it.
    let mut r = flat();
    r[20] = 1.9;
    assert_eq!(cut(&r), [(0, 19), (20, 20), (21, 39)]);
    // A step that stays.
    let mut r = flat();
    r[20..].fill(2.1);
    assert_eq!(cut(&r), [(0, 19), (20, 39)]);
    // A step of 7 cm blurred by the noise: the first point past it happens to join the
    // point before the last, but the next one does not, so the last point is no jump.
    let mut r = flat();
    r[20] = 2.04;
    r[21] = 1.985;
    r[22..].fill(1.93);
    assert_eq!(cut(&r), [(0, 20), (21, 21), (22, 39)]);
}
