//! Warnings of the libraries (a sensor link lost, a file that could not be closed) on stderr,
//! among the status lines.

use std::io::{IsTerminal, Write};

use tracing::{Event, Level, Subscriber};
use tracing_subscriber::EnvFilter;
use tracing_subscriber::fmt::format::Writer;
use tracing_subscriber::fmt::{FmtContext, FormatEvent, FormatFields, MakeWriter};
use tracing_subscriber::registry::LookupSpan;

/// What is shown without `RUST_LOG`: warnings, and the sensor link's comings and goings.
const DEFAULT_FILTER: &str = "warn,laserlines_hokuyo=info";

/// Stderr that, on a terminal, first clears the line: a status line rewritten in place
/// (`live`) is replaced by the event instead of running into it.
struct Stderr {
    tty: bool,
}

impl<'a> MakeWriter<'a> for Stderr {
    type Writer = std::io::Stderr;

    fn make_writer(&'a self) -> Self::Writer {
        let err = std::io::stderr();
        if self.tty {
            // Nothing to do if stderr is gone: the event is lost with it.
            let _ = err.lock().write_all(b"\r\x1b[K");
        }
        err
    }
}

/// An event as a status line: `laserlines: warning: sensor link lost; reconnecting
/// endpoint=... why=...`.
struct StatusLine;

impl<S, N> FormatEvent<S, N> for StatusLine
where
    S: Subscriber + for<'a> LookupSpan<'a>,
    N: for<'a> FormatFields<'a> + 'static,
{
    fn format_event(
        &self,
        ctx: &FmtContext<'_, S, N>,
        mut w: Writer<'_>,
        event: &Event<'_>,
    ) -> std::fmt::Result {
        let level = match *event.metadata().level() {
            // A library's error (a viewer's client that failed its handshake) never ends a
            // run: `laserlines: error:` alone is what a failed run ends with.
            Level::ERROR => "error (the run goes on)",
            Level::WARN => "warning",
            Level::INFO => "info",
            Level::DEBUG => "debug",
            Level::TRACE => "trace",
        };
        write!(w, "laserlines: {level}: ")?;
        ctx.field_format().format_fields(w.by_ref(), event)?;
        writeln!(w)
    }
}

/// Installs the subscriber: `RUST_LOG` (e.g. `RUST_LOG=laserlines_hokuyo=debug` for every
/// dropped scan) or [`DEFAULT_FILTER`].
pub fn init() {
    let tty = std::io::stderr().is_terminal();
    let filter =
        EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(DEFAULT_FILTER));
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(Stderr { tty })
        .with_ansi(false)
        .event_format(StatusLine)
        .init();
}
