//! What ends a live run: Ctrl-C (SIGINT, also SIGTERM and SIGHUP) and `--duration`. They set
//! the flag the stream loop and the scanner's waits watch, and the run ends with `QT`, its
//! outputs closed and its summary. While the sensor is still starting (a slow or silent
//! sensor can take seconds per command), nothing is written yet: the run ends as soon as
//! the start is done, with `QT`; a start that is not done [`GRACE`] after the stop is cut
//! there, saying that the sensor may be left streaming.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use anyhow::{Context, Result};

/// How long a stop waits for a starting sensor to be done, to tell it `QT`.
pub(super) const GRACE: Duration = Duration::from_secs(2);

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

    /// The sensor is started: true when a stop came meanwhile (the caller then tells the
    /// sensor `QT` and ends the run). Waits for a stop that is ending the process (it holds
    /// the lock until then), so that no output is begun and cut.
    pub(super) fn started(&self) -> bool {
        *self.starting.lock().unwrap_or_else(|e| e.into_inner()) = false;
        self.flag.load(Ordering::Relaxed)
    }
}

/// Sets `flag`; while the sensor is starting, also ends the process [`GRACE`] later if the
/// start is not done by then.
fn end(starting: &Arc<Mutex<bool>>, flag: &AtomicBool, why: &'static str) {
    let was = flag.swap(true, Ordering::Relaxed);
    if was || !*starting.lock().unwrap_or_else(|e| e.into_inner()) {
        return;
    }
    errln!("laserlines: {why} while the sensor is starting: ending once it is done");
    let starting = starting.clone();
    std::thread::spawn(move || {
        std::thread::sleep(GRACE);
        let still = starting.lock().unwrap_or_else(|e| e.into_inner());
        if *still {
            errln!(
                "laserlines: the sensor was not done starting {} s after the stop: ended \
                 without QT, nothing written; a sensor that had begun to stream stops at the \
                 next start or when powered off",
                GRACE.as_secs()
            );
            std::process::exit(0);
        }
    });
}
