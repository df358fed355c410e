//! Pairwise ICP on relation pairs (development aid).
use laserlines::RangeWindow;
use laserlines_slam::Se2;
use laserlines_slam::cloud::{PointCloud, SurfacePoint, scan_normals};
use laserlines_slam::icp::{IcpParams, match_points};
fn surface(scan: &laserlines::Scan) -> Vec<SurfacePoint> {
    let pts = scan.points(RangeWindow::new(0.1, 30.0f64.min(scan.range_max)));
    let normals = scan_normals(&pts, scan.angle_increment, 3);
    pts.iter().zip(normals).filter_map(|(p, n)| n.map(|normal| SurfacePoint { point: p.point, normal })).collect()
}
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let reader = laserlines_io::open(std::path::Path::new(&args[1]), None).unwrap();
    let recs: Vec<_> = reader.map(|r| r.unwrap()).collect();
    let text = std::fs::read_to_string(&args[2]).unwrap();
    let find = |t: f64| recs.iter().position(|r| (r.scan.stamp.unwrap() - t).abs() < 1e-4).unwrap();
    let mirror = std::env::var("MIRROR").is_ok();
    for l in text.lines().take(15) {
        let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
        let (a, b) = (find(v[0]), find(v[1]));
        let mut sa = recs[a].scan.clone(); let mut sb = recs[b].scan.clone();
        if mirror { sa.ranges.reverse(); sb.ranges.reverse(); }
        let pa = recs[a].pose.unwrap(); let pb = recs[b].pose.unwrap();
        let odom = Se2::new(pa.x, pa.y, pa.theta).between(&Se2::new(pb.x, pb.y, pb.theta));
        let mut c = PointCloud::new(0.02, 0.5);
        for p in surface(&sa) { c.insert(p); }
        let r = match_points(&c, &surface(&sb), odom, None, &IcpParams::default());
        match r { Ok(r) => println!("ref {:.3} {:.3} {:.4} | odom {:.3} {:.3} {:.4} | icp {:.3} {:.3} {:.4} frac {:.2}", v[2], v[3], v[7], odom.x, odom.y, odom.theta, r.pose.x, r.pose.y, r.pose.theta, r.inlier_fraction),
        Err(e) => println!("ref {:.3} {:.3} {:.4} | odom {:.3} {:.3} {:.4} | {e}", v[2], v[3], v[7], odom.x, odom.y, odom.theta) }
    }
}
