//! Steady-state extraction allocates nothing: after one warm-up call on a scan of the same
//! shape, `extract_into` with a reused extractor and buffer makes no heap allocation.
//!
//! This file is its own test binary with a counting global allocator, the one place in the
//! project that needs `unsafe` (implementing `GlobalAlloc`).

#![allow(unsafe_code, clippy::unwrap_used, clippy::expect_used)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use laserlines::Scan;

struct Counting;

thread_local! {
    /// Allocations made by this thread: the test counts its own, not those of the test
    /// harness's other threads. A `const` thread local of a type without `Drop` is never
    /// lazily set up, so reading it does not allocate.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    ALLOCATIONS.with(|a| a.set(a.get() + 1));
}

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

// SAFETY: every call is forwarded unchanged to the system allocator; the counter is per
// thread.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// A room-like scan with noise: walls at different ranges, a gap, some invalid beams.
fn scan(seed: u64) -> Scan {
    let inc = 0.3515625f64.to_radians();
    let mut state = seed;
    let ranges = (0..682)
        .map(|i| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.02;
            let phi = -2.0 + i as f64 * inc;
            let wall = match i {
                0..=199 => 1.5 / (phi + 1.0).cos().abs().max(0.2),
                200..=209 => f64::NAN,
                210..=449 => 3.0 / phi.cos().abs().max(0.3),
                _ => 2.0 / (phi - 1.2).cos().abs().max(0.2),
            };
            (wall + noise).min(5.5)
        })
        .collect();
    Scan::new(-2.0, inc, 0.02, 5.6, ranges).unwrap()
}

#[test]
fn steady_state_extraction_allocates_nothing() {
    // The counter sees this thread's allocations.
    let b = allocations();
    let v = std::hint::black_box(vec![1_u8; 16]);
    assert!(allocations() > b && v.len() == 16);
    let scans: Vec<Scan> = (0..5).map(scan).collect();
    let mut lines = Vec::with_capacity(256);
    for name in laserlines::extractors::ALGORITHMS {
        let mut ex = laserlines::extractors::by_name(name).unwrap();
        // Warm up on every scan so that buffers reach their working size.
        for s in &scans {
            ex.extract_into(s, &mut lines);
        }
        let before = allocations();
        for s in &scans {
            ex.extract_into(s, &mut lines);
        }
        let after = allocations();
        assert!(!lines.is_empty(), "{name}: no lines");
        assert_eq!(
            after - before,
            0,
            "{name}: {} allocations in steady state",
            after - before
        );
    }
}
