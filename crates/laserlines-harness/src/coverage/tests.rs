//! Tests of the coverage grid.

use super::*;
use laserlines_sim::World;

fn room() -> WorldIndex {
    let mut w = World::new();
    w.add_box(Point2::new(2.0, 1.0), 4.0, 2.0, 0.0);
    WorldIndex::new(&w, 0.5)
}

#[test]
fn reachable_area_of_a_room() {
    let index = room();
    let g = CoverageGrid::new(&index, Point2::new(2.0, 1.0), 0.3);
    // Free centres: x in [0.3, 3.7], y in [0.3, 1.7]: 34 x 14 cells of 0.1 m.
    assert!((g.reachable_cells() as i64 - 34 * 14).abs() <= 2 * (34 + 14));
    assert_eq!(g.region_kind(), CoverageRegion::Enclosed);
    assert_eq!(g.region_cells(), g.reachable_cells());
    assert!(!g.is_reachable(Point2::new(5.0, 1.0)));
    assert!(!g.is_reachable(Point2::new(0.1, 1.0)));
    assert!(g.in_arena(Point2::new(0.1, 1.0)) && !g.in_arena(Point2::new(-0.5, 1.0)));
    assert_eq!(g.coverage(), 0.0);
    // From outside the room the inside is not reachable; the walls do not enclose the
    // start, so coverage is over their bounds: the room.
    let out = CoverageGrid::new(&index, Point2::new(-0.5, 1.0), 0.3);
    assert!(!out.is_reachable(Point2::new(2.0, 1.0)));
    assert_eq!(out.region_kind(), CoverageRegion::Bounds);
    assert_eq!(out.region_cells(), g.region_cells());
    // A start on a wall reaches nothing.
    let none = CoverageGrid::new(&index, Point2::new(0.0, 1.0), 0.3);
    assert_eq!(none.reachable_cells(), 0);
    assert_eq!(none.coverage(), 0.0);
    // A start nearer a wall than the robot's radius: the room, from where it backs off
    // to; just outside the wall, not the room behind it.
    let near = CoverageGrid::new(&index, Point2::new(0.15, 1.0), 0.3);
    assert_eq!(near.reachable_cells(), g.reachable_cells());
    let behind = CoverageGrid::new(&index, Point2::new(-0.1, 1.0), 0.3);
    assert!(!behind.is_reachable(Point2::new(2.0, 1.0)));
}

#[test]
fn coverage_is_over_the_whole_arena_not_the_start_pocket() {
    // A 6 m x 4 m arena; a 1 m x 1 m pocket inside it, closed but for a gap of 0.3 m
    // (narrower than the robot): a start in the pocket counts the whole arena, and a
    // 1 m door in the outer wall does not open it.
    let mut w = World::new();
    w.add_polygon(&[
        Point2::new(6.0, 4.0),
        Point2::new(0.0, 4.0),
        Point2::new(0.0, 0.0),
        Point2::new(6.0, 0.0),
        Point2::new(6.0, 1.5),
    ]);
    w.walls.pop();
    w.add_segment(Point2::new(6.0, 2.5), Point2::new(6.0, 4.0));
    w.add_segment(Point2::new(1.0, 1.0), Point2::new(2.0, 1.0));
    w.add_segment(Point2::new(2.0, 1.0), Point2::new(2.0, 2.0));
    w.add_segment(Point2::new(2.0, 2.0), Point2::new(1.0, 2.0));
    w.add_segment(Point2::new(1.0, 2.0), Point2::new(1.0, 1.65));
    w.add_segment(Point2::new(1.0, 1.35), Point2::new(1.0, 1.0));
    let index = WorldIndex::new(&w, 0.5);
    let pocket = CoverageGrid::new(&index, Point2::new(1.5, 1.5), 0.32);
    assert_eq!(pocket.region_kind(), CoverageRegion::Enclosed);
    assert!(
        pocket.reachable_area_m2() < 0.2,
        "{}",
        pocket.reachable_area_m2()
    );
    assert!(
        pocket.region_area_m2() > 10.0,
        "{}",
        pocket.region_area_m2()
    );
    // Seeing all of the pocket is a small part of the arena.
    let mut p = pocket.clone();
    let n = 720;
    let ranges: Vec<f64> = (0..n)
        .map(|i| {
            let a = -std::f64::consts::PI + i as f64 * std::f64::consts::TAU / n as f64;
            index
                .cast(Point2::new(1.5, 1.5), a, 10.0)
                .map_or(f64::NAN, |h| h.range)
        })
        .collect();
    let at = Isometry2::new(Vector2::new(1.5, 1.5), 0.0);
    p.mark_scan(
        &at,
        -std::f64::consts::PI,
        std::f64::consts::TAU / n as f64,
        &ranges,
        5.6,
    );
    assert!((p.reachable_coverage() - 1.0).abs() < 1e-12);
    assert!(p.coverage() < 0.1, "{}", p.coverage());
    // Open the arena's outer wall by 3 m (wider than a wall element): a start inside is
    // no longer enclosed, and coverage is over the walls' bounds.
    let mut open = World::new();
    open.add_polygon(&[
        Point2::new(0.0, 0.0),
        Point2::new(6.0, 0.0),
        Point2::new(6.0, 4.0),
        Point2::new(0.0, 4.0),
    ]);
    open.walls.remove(1);
    open.add_segment(Point2::new(6.0, 0.0), Point2::new(6.0, 0.5));
    open.add_segment(Point2::new(6.0, 3.5), Point2::new(6.0, 4.0));
    let index = WorldIndex::new(&open, 0.5);
    let g = CoverageGrid::new(&index, Point2::new(3.0, 2.0), 0.32);
    assert_eq!(g.region_kind(), CoverageRegion::Bounds);
    assert!(g.in_arena(Point2::new(5.9, 2.0)));
    assert!(!g.in_arena(Point2::new(6.5, 2.0)));
}

#[test]
fn scans_mark_the_cells_they_sweep() {
    let index = room();
    let mut g = CoverageGrid::new(&index, Point2::new(2.0, 1.0), 0.3);
    // Three beams 0.05 rad apart, 3.45 m long, from 1.3 cm above the centre line of the
    // row y in [1.0, 1.1].
    let pose = Isometry2::new(Vector2::new(0.55, 1.063), 0.0);
    g.mark_scan(&pose, -0.05, 0.05, &[3.45, 3.45, 3.45], 5.6);
    assert!(g.is_seen(Point2::new(2.0, 1.05)));
    assert!(g.is_seen(Point2::new(3.95, 1.05)));
    assert!(!g.is_seen(Point2::new(2.0, 1.25)));
    assert!(!g.is_seen(Point2::new(0.65, 1.05)));
    // The fan's half-width is 0.05 d at d from the laser. Reachable centres (x = 0.35
    // .. 3.65) inside it: on the row y = 1.05 (1.3 cm off the axis) from d > 0.26,
    // x = 0.85 .. 3.65 (29 cells); on y = 1.15 (8.7 cm off) from d > 1.74, x = 2.35 ..
    // 3.65 (14); on y = 0.95 (11.3 cm off) from d > 2.26, x = 2.85 .. 3.65 (9).
    assert_eq!(g.seen_cells(), 29 + 14 + 9);
    // One beam sweeps nothing.
    let mut one = CoverageGrid::new(&index, Point2::new(2.0, 1.0), 0.3);
    one.mark_scan(&pose, 0.0, 0.1, &[3.45], 5.6);
    assert_eq!(one.seen_cells(), 0);
    // A full turn of beams to the walls sees the whole room.
    let n = 3600;
    let ranges: Vec<f64> = (0..n)
        .map(|i| {
            let a = -std::f64::consts::PI + i as f64 * std::f64::consts::TAU / n as f64;
            index
                .cast(Point2::new(2.0, 1.0), a, 10.0)
                .map_or(f64::NAN, |h| h.range)
        })
        .collect();
    let centre = Isometry2::new(Vector2::new(2.0, 1.0), 0.0);
    g.mark_scan(
        &centre,
        -std::f64::consts::PI,
        std::f64::consts::TAU / n as f64,
        &ranges,
        5.6,
    );
    assert!((g.coverage() - 1.0).abs() < 1e-12, "{}", g.coverage());
}

#[test]
fn a_gap_wider_than_the_outline_closes_opens_the_arena() {
    // An 8 m x 6 m arena whose bottom wall has a 2.5 m gap, and a 1 m corridor along
    // its left wall that the outline's disc (1.3 m) cannot enter: a start in the corridor
    // is in the arena's bounds, and so is the open floor it leads to.
    let mut w = World::new();
    let p = Point2::new;
    w.add_segment(p(0.0, 0.0), p(2.75, 0.0));
    w.add_segment(p(5.25, 0.0), p(8.0, 0.0));
    w.add_segment(p(8.0, 0.0), p(8.0, 6.0));
    w.add_segment(p(8.0, 6.0), p(0.0, 6.0));
    w.add_segment(p(0.0, 6.0), p(0.0, 0.0));
    w.add_segment(p(1.0, 1.2), p(1.0, 6.0));
    let index = WorldIndex::new(&w, 0.5);
    let outline = ArenaOutline::of_index(&index);
    assert!(outline.encloses(p(0.5, 4.0)) && !outline.encloses(p(4.0, 3.0)));
    let g = CoverageGrid::new(&index, p(0.5, 4.0), 0.32);
    assert_eq!(g.region_kind(), CoverageRegion::Bounds);
    assert!(g.in_arena(p(4.0, 3.0)) && g.in_arena(p(0.5, 4.0)));
    assert!(!g.in_arena(p(4.0, -0.5)));
}
