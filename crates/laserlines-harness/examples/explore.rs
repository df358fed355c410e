//! Runs the explorer in `.raf` arenas or seeded mazes and prints the metrics of each run.
//!
//! ```sh
//! cargo run --release -p laserlines-harness --example explore -- data/arenas/maze_10m_x_14m.raf 0 5
//! cargo run --release -p laserlines-harness --example explore -- maze:3:islands 0 5
//! ```
//! Arguments: an arena (a `.raf` path, or `maze:SEED` / `maze:SEED:islands`), the first
//! seed, the number of seeds, and optionally the duration in seconds (default 900).

use laserlines::robot::Footprint;
use laserlines_harness::{RunConfig, run};
use laserlines_sim::arena::{ArenaOptions, interior_start, load_raf};
use laserlines_sim::maze::{MazeParams, generate};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let what = args.first().cloned().unwrap_or_else(|| "maze:1".to_owned());
    let first: u64 = args.get(1).map_or(Ok(0), |s| s.parse())?;
    let count: u64 = args.get(2).map_or(Ok(1), |s| s.parse())?;
    let duration: f64 = args.get(3).map_or(Ok(900.0), |s| s.parse())?;
    let (world, start) = if let Some(rest) = what.strip_prefix("maze:") {
        let mut parts = rest.split(':');
        let seed: u64 = parts.next().unwrap_or("1").parse()?;
        let islands = usize::from(parts.next() == Some("islands")) * 3;
        let m = generate(
            &MazeParams {
                islands,
                ..MazeParams::default()
            },
            seed,
        );
        (m.world, m.start)
    } else {
        let a = load_raf(std::path::Path::new(&what), &ArenaOptions::default())?;
        let start = interior_start(&a.world, Footprint::naji_v().circumradius())
            .ok_or("no enclosed free region in the arena")?;
        eprintln!("start {:?}", start.translation.vector);
        (a.world, start)
    };
    for seed in first..first + count {
        let config = RunConfig {
            duration_s: duration,
            seed,
            ..RunConfig::default()
        };
        let r = run(&world, start, &config)?;
        let m = r.metrics;
        println!(
            "seed {seed:3}: coverage {:.3} collisions {} min_clearance {:.3} path {:.1} m t90 {:?} loops {} frontiers {} pose_err {:.2} m {:.3} rad wall {:.2} s ({:.0}x) stop {}",
            m.coverage,
            m.collisions,
            m.min_clearance_m,
            m.path_length_m,
            m.time_to_90_percent_s.map(|t| t.round()),
            m.loops,
            m.frontiers,
            m.max_pose_error_m,
            m.max_heading_error_rad,
            m.wall_time_s,
            m.sim_time_s / m.wall_time_s,
            m.stop.name()
        );
    }
    Ok(())
}
