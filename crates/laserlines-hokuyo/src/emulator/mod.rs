//! A SCIP 2.0 sensor in software: the server side of the protocol, fed with ranges by a
//! [`ScanFeed`], with injectable faults, over TCP or a pseudo-terminal.
//!
//! - [`Model`]: what the emulated sensor says about itself (`urg-04lx`, `ust-10lx`);
//! - [`ScanFeed`]: where its ranges come from (here [`PatternFeed`]; the simulator and
//!   recorded logs feed it in `laserlines-hokuyo-emulator`);
//! - [`Faults`]: bad check characters, cut lines, dropped connections, a start in SCIP
//!   1.1, slow replies, a stalled stream, a clock about to wrap;
//! - [`Emulator`]: serves one host at a time, on TCP ([`Emulator::serve_tcp`]) or a
//!   pseudo-terminal ([`Emulator::serve_pty`]); every scan it sends is logged ([`Served`]).

mod encode;
mod model;
mod sensor;
mod server;

pub use encode::{info_reply, scan_message, simple_reply};
pub use model::{Model, ModelName};
pub use sensor::Action;
pub use sensor::{Faults, Sensor};
pub use server::{Emulator, EmulatorHandle, Served, ServedFault, ServedLog};

/// Where the emulator's ranges come from.
pub trait ScanFeed: Send {
    /// The readings of the next scan, mm, one per step `AMIN..=AMAX` of `model` (error
    /// codes below `DMIN` allowed). A feed that has run out repeats itself or returns what
    /// it likes; the emulator fills missing steps with 0 (no echo).
    fn next_scan(&mut self, model: &Model) -> Vec<u32>;
}

/// A feed for tests: a room-like profile that changes from scan to scan, with error codes
/// (0 to 19) at regular places, so that every encoding path and error code is exercised.
#[derive(Debug, Clone, Default)]
pub struct PatternFeed {
    scan: u64,
}

impl PatternFeed {
    /// A feed starting at scan 0.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }
}

impl ScanFeed for PatternFeed {
    fn next_scan(&mut self, model: &Model) -> Vec<u32> {
        let steps = (model.amax - model.amin + 1) as usize;
        let k = self.scan;
        self.scan += 1;
        let span = u64::from(model.dmax_mm - model.dmin_mm);
        (0..steps as u64)
            .map(|i| {
                if (i + k).is_multiple_of(37) {
                    // Every error code in turn.
                    ((i / 37 + k) % 20) as u32
                } else {
                    let v = (i * 97 + k * 13) % span.max(1);
                    model.dmin_mm + v as u32
                }
            })
            .collect()
    }
}
