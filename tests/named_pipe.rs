//! A named pipe fed with bytes on another thread, as the readers of every crate meet one
//! (`/dev/stdin`, `<(cmd)`, `mkfifo`). Each test crate that needs it includes this file:
//! `#[path = "../../../tests/named_pipe.rs"] mod named_pipe;`.

#![allow(dead_code)]

use std::path::Path;

/// `read` of a named pipe called `name` through which `bytes` are written; `None`, with a
/// notice, where `mkfifo` is not available.
#[cfg(unix)]
pub fn through_named_pipe<T>(
    name: &str,
    bytes: Vec<u8>,
    read: impl FnOnce(&Path) -> T,
) -> Option<T> {
    let dir = std::env::temp_dir().join(format!("laserlines-fifo-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).ok()?;
    let fifo = dir.join(name);
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("note: mkfifo is not available; the named-pipe case is not run");
        return None;
    }
    let writer = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::write(fifo, bytes))
    };
    let out = read(&fifo);
    let written = writer.join();
    std::fs::remove_dir_all(&dir).ok()?;
    assert!(written.is_ok_and(|w| w.is_ok()), "the pipe's writer failed");
    Some(out)
}
