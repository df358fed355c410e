//! Arbitrary bytes through the TUM trajectory and relations readers: they must never panic,
//! every pose they return is finite, and every error names the input.
#![no_main]

use libfuzzer_sys::fuzz_target;
use laserlines_io::trajectory::{read_relations, read_tum};

fuzz_target!(|data: &[u8]| {
    match read_tum("fuzz", data) {
        Ok(poses) => {
            for p in poses {
                assert!(p.t.is_finite() && p.pose.is_finite());
            }
        }
        Err(e) => assert_eq!(e.file(), "fuzz"),
    }
    match read_relations("fuzz", data) {
        Ok(rels) => {
            for r in rels {
                assert!(r.t1.is_finite() && r.t2.is_finite() && r.delta.is_finite());
            }
        }
        Err(e) => assert_eq!(e.file(), "fuzz"),
    }
});
