//! Probe.
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let reader = laserlines_io::reader::open(std::path::Path::new(&path), None).unwrap();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let mut lines = Vec::new();
    for rec in reader {
        let rec = rec.unwrap();
        hs.extract_into(&rec.scan, &mut lines);
        let st = hs.stages();
        println!("noise {}", st.noise());
        let removed = st.removed();
        // compress runs
        let mut runs = Vec::new();
        let mut i = 0;
        while i < removed.len() {
            let s = removed[i];
            let mut e = s;
            while i + 1 < removed.len() && removed[i + 1] == e + 1 {
                i += 1;
                e += 1;
            }
            runs.push((s, e));
            i += 1;
        }
        println!(
            "removed {} beams in runs {:?}",
            removed.len(),
            &runs[..runs.len().min(60)]
        );
        for (seg, splits) in st.segments().zip(st.split_points()) {
            println!(
                "segment {}..{} ({} points), splits {splits:?}",
                seg.first, seg.last, seg.points
            );
        }
        for l in &lines {
            println!(
                "line {}..{} r {:.4} a {:.2} n {} rms {:.4}",
                l.first,
                l.last,
                l.r,
                l.alpha.to_degrees(),
                l.points,
                l.rms
            );
        }
    }
}
