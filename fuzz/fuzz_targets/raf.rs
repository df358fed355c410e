//! Arbitrary text through the RoboCup Rescue arena (`.raf`) parser: it must never panic;
//! an arena holds only finite walls and discs and reports what it ignored, an error names
//! the input.
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
    match parse_raf(
        &text,
        "fuzz.raf",
        &ArenaOptions {
            wall_length: length,
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
            let _ = arena.report.ignored_count();
        }
        Err(e) => assert!(e.to_string().contains("fuzz.raf"), "{e}"),
    }
});
