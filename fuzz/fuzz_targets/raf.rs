//! Arbitrary text through the RoboCup Rescue arena (`.raf`) parser: it must never panic;
//! an arena holds only finite walls and discs and accounts for every element (in the
//! laser's plane, out of it or skipped), an error names the input.
#![no_main]

use laserlines_sim::arena::{ArenaOptions, WallLength, parse_raf};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let length = if data.first().is_some_and(|b| b % 2 == 1) {
        WallLength::Mesh
    } else {
        WallLength::Full
    };
    // Laser heights from 0.05 m to 1.3 m, through the ramps, treads, holes and boxes.
    let laser_height = 0.05 + f64::from(data.get(1).copied().unwrap_or(80)) / 200.0;
    match parse_raf(
        &text,
        "fuzz.raf",
        &ArenaOptions {
            wall_length: length,
            laser_height,
        },
    ) {
        Ok(arena) => {
            let finite = |p: laserlines::math::Point2| p.x.is_finite() && p.y.is_finite();
            assert!(!arena.world.walls.is_empty() || !arena.world.discs.is_empty());
            assert!(arena.world.walls.iter().all(|w| finite(w.a) && finite(w.b)));
            assert!(
                arena
                    .world
                    .discs
                    .iter()
                    .all(|d| finite(d.centre) && d.radius.is_finite() && d.radius > 0.0)
            );
            let r = &arena.report;
            let counted: usize = [&r.in_plane, &r.out_of_plane, &r.skipped]
                .iter()
                .flat_map(|m| m.values())
                .sum();
            assert_eq!(counted, r.elements);
        }
        Err(e) => assert!(e.to_string().contains("fuzz.raf"), "{e}"),
    }
});
