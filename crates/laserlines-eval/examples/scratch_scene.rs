//! scratch
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use laserlines_sim::{LaserModel, Rng, scenes};
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let kind = a[1].as_str();
    let seed: u64 = a[2].parse().unwrap();
    let lo: usize = a.get(3).and_then(|s| s.parse().ok()).unwrap_or(0);
    let hi: usize = a.get(4).and_then(|s| s.parse().ok()).unwrap_or(681);
    let make: fn(&mut Rng) -> scenes::Scene = match kind {
        "boxes" => scenes::boxes_in_room,
        "room" => scenes::rectangular_room,
        "corridor" => scenes::corridor_with_door_gap,
        "corner" => scenes::corner,
        _ => scenes::grazing_wall,
    };
    let model = LaserModel::urg04lx();
    let mut rng = Rng::new(seed);
    let scene = make(&mut rng);
    let sim = scene.simulate(&model, &mut rng);
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let lines = hs.extract(&sim.scan);
    let st = hs.stages();
    println!(
        "noise {} bands {:?}",
        st.noise(),
        st.noise_bands()
            .iter()
            .filter(|b| b.samples > 0)
            .map(|b| (b.range, b.samples, b.sigma))
            .collect::<Vec<_>>()
    );
    for s in st.segments() {
        if s.last >= lo && s.first <= hi {
            println!("segment {:?}", s);
        }
    }
    for sp in st.split_points() {
        println!("splits {:?}", sp);
    }
    for l in &lines {
        if l.last >= lo && l.first <= hi {
            println!(
                "line {}..{} r {:.3} a {:.2} len {:.2} rms {:.4} n {}",
                l.first,
                l.last,
                l.r,
                l.alpha.to_degrees(),
                l.length(),
                l.rms,
                l.points
            );
        }
    }
    let removed = st.removed();
    println!(
        "removed in range: {:?}",
        removed
            .iter()
            .filter(|&&i| i >= lo && i <= hi)
            .collect::<Vec<_>>()
    );
    for i in lo..=hi.min(sim.scan.ranges.len() - 1) {
        print!("{}:{:.3} ", i, sim.scan.ranges[i]);
    }
    println!();
    for p in &sim.truth.pieces {
        if p.last >= lo && p.first <= hi {
            println!("truth {:?}", (p.wall, p.first, p.last));
        }
    }
}
