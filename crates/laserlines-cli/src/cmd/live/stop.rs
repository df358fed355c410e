//! What ends a live run: Ctrl-C (SIGINT, also SIGTERM and SIGHUP) and `--duration`. Once the
//! scans flow, they set the flag the stream loop and the scanner's waits watch, and the run
//! ends with `QT`, its outputs closed and its summary. While the sensor is still starting
//! (a slow or silent sensor can take seconds per command), nothing is written yet: the
//! process ends there and then, saying so.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use anyhow::{Context, Result};

/// The stop flag and whether the sensor is still starting.
pub(super) struct Stop {
    flag: Arc<AtomicBool>,
    starting: Arc<Mutex<bool>>,
}

impl Stop {
    /// Catches Ctrl-C (and SIGTERM, SIGHUP) and starts the `duration`'s clock.
    pub(super) fn install(duration: Option<Duration>) -> Result<Self> {
        let stop = Self {
            flag: Arc::new(AtomicBool::new(false)),
            starting: Arc::new(Mutex::new(true)),
        };
        let (flag, starting) = (stop.flag.clone(), stop.starting.clone());
        ctrlc::set_handler(move || end(&starting, &flag, "stopped (Ctrl-C or a signal)"))
            .context("cannot catch Ctrl-C")?;
        // The duration ends the run even while the sensor is away (the scanner then waits to
        // reconnect, and only the flag ends its wait).
        if let Some(d) = duration {
            let (flag, starting) = (stop.flag.clone(), stop.starting.clone());
            std::thread::spawn(move || {
                std::thread::sleep(d);
                end(&starting, &flag, "--duration ran out");
            });
        }
        Ok(stop)
    }

    /// The flag the stream watches.
    pub(super) fn flag(&self) -> &AtomicBool {
        &self.flag
    }

    /// The sensor is streaming: from now on a stop ends the run through the flag. Waits for
    /// a stop that is ending the process (it holds the lock until then), so that no output
    /// is begun and cut.
    pub(super) fn started(&self) {
        *self.starting.lock().unwrap_or_else(|e| e.into_inner()) = false;
    }
}

/// Ends the run: the process itself while the sensor is starting, else through `flag`.
fn end(starting: &Mutex<bool>, flag: &AtomicBool, why: &str) {
    let starting = starting.lock().unwrap_or_else(|e| e.into_inner());
    if *starting {
        errln!("laserlines: {why} while the sensor was starting: no scan read, nothing written");
        std::process::exit(0);
    }
    flag.store(true, Ordering::Relaxed);
}
