//! Cutting the byte stream into messages at every `\n\n`.

/// The largest message accepted, bytes. A scan of 1081 steps in 3-character encoding is
/// about 3.4 kB; a stream that goes this long without a message end is not SCIP.
pub const MAX_MESSAGE: usize = 64 * 1024;

/// Cuts a byte stream into messages at every `\n\n`.
///
/// Push what the transport read with [`Framer::push`], then take whole messages with
/// [`Framer::next_message`]. A stream that runs past [`MAX_MESSAGE`] bytes without a
/// message end is dropped (and counted) rather than buffered without bound.
#[derive(Debug, Default, Clone)]
pub struct Framer {
    buf: Vec<u8>,
    /// Where the search for `\n\n` goes on from.
    scanned: usize,
    overflows: u64,
}

impl Framer {
    /// An empty framer.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends bytes read from the transport.
    pub fn push(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// The next whole message (ending with `\n\n`), if one is buffered. A leading line feed
    /// left over between messages is skipped.
    pub fn next_message(&mut self) -> Option<Vec<u8>> {
        // Stray line feeds before a message (e.g. after a host line ending of CR LF
        // echoed back) carry nothing.
        let lead = self.buf.iter().take_while(|&&b| b == b'\n').count();
        if lead > 0 {
            self.buf.drain(..lead);
            self.scanned = 0;
        }
        let from = self.scanned.saturating_sub(1);
        if let Some(pos) = self.buf[from..].windows(2).position(|w| w == b"\n\n") {
            let end = from + pos + 2;
            let message: Vec<u8> = self.buf.drain(..end).collect();
            self.scanned = 0;
            return Some(message);
        }
        self.scanned = self.buf.len();
        if self.buf.len() > MAX_MESSAGE {
            self.buf.clear();
            self.scanned = 0;
            self.overflows += 1;
        }
        None
    }

    /// Bytes buffered that do not yet make a whole message.
    #[must_use]
    pub fn pending(&self) -> usize {
        self.buf.len()
    }

    /// Drops everything buffered (after a reconnect).
    pub fn clear(&mut self) {
        self.buf.clear();
        self.scanned = 0;
    }

    /// Times more than [`MAX_MESSAGE`] bytes came without a message end.
    #[must_use]
    pub fn overflows(&self) -> u64 {
        self.overflows
    }
}
