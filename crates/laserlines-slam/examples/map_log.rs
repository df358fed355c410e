//! Maps a log and scores it against relations (development aid).
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use laserlines_slam::{Mapper, MapperParams, Relation, Se2, score_relations};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut reader = laserlines_io::open(std::path::Path::new(&args[1]), None).unwrap();
    let odom = args.get(3).map(|s| s != "off").unwrap_or(true);
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let mut params = MapperParams::default();
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<f64>().ok());
    if let Some(v) = env("LOOPS") { params.loops.every_scans = v as usize; }
    if let Some(v) = env("MAXR") { params.max_range_m = v; }
    if let Some(v) = env("SPS") { params.scans_per_submap = v as usize; }
    if let Some(v) = env("CORR") { params.icp.max_correspondence_m = v; }
    if let Some(v) = env("FRAC") { params.icp.min_inlier_fraction = v; }
    if let Some(v) = env("STD") { params.icp.max_std_m = v; params.icp.max_std_rad = v; }
    if let Some(v) = env("SCORE") { params.loops.min_score = v; }
    if let Some(v) = env("LFRAC") { params.loops.min_inlier_fraction = v; }
    if let Some(v) = env("WIN") { params.loops.linear_window_m = v; }
    if let Some(v) = env("RAD") { params.loops.search_radius_m = v; }
    if let Some(v) = env("CONF") { params.confident_fraction = v; }
    if let Some(v) = env("SKIP") { params.loops.skip_after_closure_scans = v as usize; }
    if let Some(v) = env("EVERY") { params.loops.every_scans = v as usize; }
    if let Some(v) = env("GRES") { params.loops.grid_resolution_m = v; }
    if let Some(v) = env("ANG") { params.loops.angular_window_rad = v; }
    if let Some(v) = env("CT") { params.icp.converge_translation_m = v; params.icp.converge_rotation_rad = v / 10.0; }
    if let Some(v) = env("ITER") { params.icp.max_iterations = v as usize; }
    if let Some(v) = env("VOX") { params.voxel_m = v; }
    if let Some(v) = env("MW") { params.motion_window_m = v; }
    if let Some(v) = env("MA") { params.motion_window_rad = v; }
    if let Some(v) = env("MS") { params.motion_min_score = v; }
    if let Some(v) = env("OPTE") { params.loops.optimize_every_scans = v as usize; }
    if let Some(v) = env("COVS") { params.match_covariance_scale = v; }
    let mut errs = std::collections::BTreeMap::<String, usize>::new();
    let mut mapper = Mapper::new(params);
    let mut lines = Vec::new();
    let t0 = std::time::Instant::now();
    let mut stamps = Vec::new();
    let mut odoms = Vec::new();
    let mut prev_odom = Se2::IDENTITY;
    while let Some(r) = reader.next() {
        let r = r.unwrap();
        hs.extract_into(&r.scan, &mut lines);
        let o = if odom { r.pose.map(|p| Se2::new(p.x, p.y, p.theta)) } else { None };
        let u = mapper.add_scan(&r.scan, &lines, o).unwrap();
        if std::env::var("BIG").is_ok() && u.node > 0 {
            let p = mapper.poses(); let od = r.pose.unwrap(); let o = Se2::new(od.x, od.y, od.theta);
            let d = p[u.node - 1].between(&p[u.node]); let od0 = prev_odom.between(&o);
            if (d.theta - od0.theta).abs() > 0.03 { eprintln!("{} dtheta match {:.3} odom {:.3} dxy {:.3} {:.3} vs {:.3} {:.3} err {:?}", u.node, d.theta, od0.theta, d.x, d.y, od0.x, od0.y, u.match_error); }
        }
        if let Some(od) = r.pose { prev_odom = Se2::new(od.x, od.y, od.theta); }
        if std::env::var("TRACE").is_ok() && (u.node % 25 == 0 && u.node < 700) { let od = r.pose.unwrap(); eprintln!("{} pose {:.3} {:.3} {:.4} odom {:.3} {:.3} {:.4} err {:?}", u.node, u.pose.x, u.pose.y, u.pose.theta, od.x, od.y, od.theta, u.match_error); }
        if let Some(e) = u.match_error { let k = format!("{e:?}"); *errs.entry(k.split(['{',' ']).next().unwrap().to_string()).or_default() += 1; }
        stamps.push(r.scan.stamp.unwrap_or(0.0));
        odoms.push(r.pose.map(|p| Se2::new(p.x, p.y, p.theta)).unwrap_or_default());
    }
    let t1 = t0.elapsed().as_secs_f64();
    mapper.optimize().unwrap();
    eprintln!("{errs:?}");
    eprintln!("{:?} in {:.2} s (+{:.2} s final opt)", mapper.stats(), t1, t0.elapsed().as_secs_f64() - t1);
    if let Ok(out) = std::env::var("DUMP") {
        use std::io::Write;
        let mut f = std::io::BufWriter::new(std::fs::File::create(out).unwrap());
        for (i, (p, sc)) in mapper.poses().iter().zip(mapper.scans()).enumerate() {
            writeln!(f, "T {} {} {}", p.x, p.y, p.theta).unwrap();
            if i % 4 == 0 { for q in sc.points.iter().step_by(2) { let w = p.transform(*q); writeln!(f, "P {} {}", w.x, w.y).unwrap(); } }
        }
        for e in mapper.graph().edges() { if e.to != e.from + 1 { let a = mapper.poses()[e.from]; let b = mapper.poses()[e.to]; writeln!(f, "L {} {} {} {}", a.x, a.y, b.x, b.y).unwrap(); } }
    }
    if std::env::var("SELF").is_ok() {
        let refs: Vec<(f64, Se2)> = stamps.iter().copied().zip(odoms.iter().copied()).enumerate().map(|(i, (t, p))| (if t == 0.0 { i as f64 } else { t }, p)).collect();
        let rels = laserlines_slam::eval::relations_from_trajectory(&refs, 5);
        let traj: Vec<(f64, Se2)> = refs.iter().map(|r| r.0).zip(mapper.poses().iter().copied()).collect();
        let s = score_relations(&traj, &rels).unwrap();
        eprintln!("self n {} trans {:.4} ± {:.4} (max {:.3}) rot {:.3} ± {:.3} deg (max {:.2})", s.n, s.translation_m.mean, s.translation_m.std, s.translation_m.max, s.rotation_deg.mean, s.rotation_deg.std, s.rotation_deg.max);
    }
    if let Some(rel) = args.get(2).filter(|s| *s != "-") {
        let text = std::fs::read_to_string(rel).unwrap();
        let rels: Vec<Relation> = text.lines().filter(|l| !l.trim().is_empty()).map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            Relation { t1: v[0], t2: v[1], delta: Se2::new(v[2], v[3], v[7]) }
        }).collect();
        let poses: Vec<Se2> = if std::env::var("ODOMSCORE").is_ok() { odoms.clone() } else { mapper.poses().to_vec() };
        let traj: Vec<(f64, Se2)> = stamps.iter().copied().zip(poses.iter().copied()).collect();
        let s = score_relations(&traj, &rels).unwrap();
        let (mut ss, mut sl) = (vec![], vec![]);
        for (r, e) in rels.iter().zip(&s.errors) { if r.t2 - r.t1 < 5.0 { ss.push(*e) } else { sl.push(*e) } }
        let m = |v: &Vec<(f64,f64)>| (v.len(), v.iter().map(|e| e.0).sum::<f64>() / v.len() as f64, v.iter().map(|e| e.1).sum::<f64>() / v.len() as f64);
        eprintln!("short {:?} long {:?}", m(&ss), m(&sl));
        if let Ok(f) = std::env::var("ERRS") {
            use std::io::Write;
            let mut w = std::fs::File::create(f).unwrap();
            for (r, e) in rels.iter().zip(&s.errors) {
                let find = |t: f64| traj.iter().min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs())).unwrap().1;
                let d = find(r.t1).between(&find(r.t2));
                writeln!(w, "{} {} {} {} {} {} {} {} {}", r.t2 - r.t1, r.delta.x, r.delta.y, r.delta.theta, d.x, d.y, d.theta, e.0, e.1).unwrap();
            }
        }
        eprintln!("n {} trans {:.4} ± {:.4} (max {:.3}) rot {:.3} ± {:.3} deg (max {:.2})", s.n, s.translation_m.mean, s.translation_m.std, s.translation_m.max, s.rotation_deg.mean, s.rotation_deg.std, s.rotation_deg.max);
    }
}
