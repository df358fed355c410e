//! Gzip input of one or more members (as `cat a.gz b.gz > ab.gz` makes), read member by
//! member, so that bytes after the last member that do not start another (trailing garbage,
//! which `gzip -d` warns of and drops) end the input with an error that says so, after every
//! byte of the members before them.

use std::io::{self, BufRead, Read};

use flate2::bufread::GzDecoder;

use crate::reader::Input;

/// The two bytes every gzip member starts with.
pub(crate) const MAGIC: [u8; 2] = [0x1f, 0x8b];
const ID1: u8 = MAGIC[0];
const ID2: u8 = MAGIC[1];

/// The error of bytes after the last member that are not another member (zero bytes up to the
/// end are padding, not garbage).
pub const TRAILING_GARBAGE: &str = "bytes after the end of the gzip data that do not start \
     another gzip member (trailing garbage; everything before them was read)";

/// The error inside the [`io::Error`] of trailing garbage: everything before it was whole
/// (so a last line without its line end, just before it, is a whole line).
#[derive(Debug)]
pub struct TrailingGarbage;

impl std::fmt::Display for TrailingGarbage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(TRAILING_GARBAGE)
    }
}

impl std::error::Error for TrailingGarbage {}

impl TrailingGarbage {
    /// True when `e` is the error of trailing garbage.
    #[must_use]
    pub fn is(e: &io::Error) -> bool {
        e.get_ref().is_some_and(|inner| inner.is::<Self>())
    }
}

/// The decompressed bytes of the gzip members of an input.
pub(crate) struct Members {
    decoder: Option<GzDecoder<Input>>,
}

impl Members {
    pub(crate) fn new(input: Input) -> Self {
        Self {
            decoder: Some(GzDecoder::new(input)),
        }
    }
}

impl Read for Members {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        while let Some(decoder) = self.decoder.as_mut() {
            let n = match decoder.read(buf) {
                Ok(n) => n,
                // Tried again by the caller: the decoder keeps its place.
                Err(e) if e.kind() == io::ErrorKind::Interrupted => return Err(e),
                Err(e) => {
                    // A damaged member ends the input: nothing after it is read.
                    self.decoder = None;
                    return Err(e);
                }
            };
            if n > 0 || buf.is_empty() {
                return Ok(n);
            }
            // The member ended (a finished decoder reads 0 again, so an interrupted look at
            // what follows is tried again from here): the end, another member, or garbage.
            match after_member(decoder.get_mut())? {
                After::End => self.decoder = None,
                After::Member => {
                    let rest = self.decoder.take().map(GzDecoder::into_inner);
                    self.decoder = rest.map(GzDecoder::new);
                }
                After::Garbage => {
                    self.decoder = None;
                    return Err(io::Error::new(io::ErrorKind::InvalidData, TrailingGarbage));
                }
            }
        }
        Ok(0)
    }
}

/// What follows a member.
enum After {
    End,
    Member,
    Garbage,
}

/// What `rest` holds after a member: the end (or zero bytes up to it: the padding of a tape
/// or a block device, which `gzip -d` drops without a word), another member, or garbage.
fn after_member(rest: &mut Input) -> io::Result<After> {
    loop {
        let head = rest.fill_buf()?;
        let zeros = head.iter().take_while(|&&b| b == 0).count();
        if zeros == 0 {
            return Ok(match head {
                [] => After::End,
                [ID1, ID2, ..] => After::Member,
                // The second byte beyond the buffer: the member's header says the rest.
                [ID1] => After::Member,
                _ => After::Garbage,
            });
        }
        rest.consume(zeros);
    }
}

#[cfg(test)]
mod tests {
    use std::io::{Cursor, Write};

    use flate2::Compression;
    use flate2::write::GzEncoder;

    use super::*;

    fn gz(text: &[u8]) -> Vec<u8> {
        let mut e = GzEncoder::new(Vec::new(), Compression::default());
        e.write_all(text).unwrap();
        e.finish().unwrap()
    }

    fn read(bytes: Vec<u8>) -> (Vec<u8>, Option<String>) {
        read_from(Box::new(Cursor::new(bytes)))
    }

    /// Reads `input` through [`Members`] in small pieces, trying again when interrupted.
    fn read_from(input: Input) -> (Vec<u8>, Option<String>) {
        let mut m = Members::new(input);
        let mut out = Vec::new();
        let mut buf = [0u8; 7];
        loop {
            match m.read(&mut buf) {
                Ok(0) => return (out, None),
                Ok(n) => out.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return (out, Some(e.to_string())),
            }
        }
    }

    /// Bytes whose reader is interrupted once, when it reaches byte `at`.
    struct InterruptedAt {
        bytes: Cursor<Vec<u8>>,
        at: u64,
    }

    impl Read for InterruptedAt {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = io::BufRead::fill_buf(self)?.len().min(buf.len());
            buf[..n].copy_from_slice(&self.bytes.get_ref()[self.bytes.position() as usize..][..n]);
            self.consume(n);
            Ok(n)
        }
    }

    impl io::BufRead for InterruptedAt {
        fn fill_buf(&mut self) -> io::Result<&[u8]> {
            if self.bytes.position() == self.at {
                self.at = u64::MAX;
                return Err(io::Error::from(io::ErrorKind::Interrupted));
            }
            // Never past `at`, so that the interruption comes there.
            let end = if self.at > self.bytes.position() {
                self.at.min(self.bytes.get_ref().len() as u64)
            } else {
                self.bytes.get_ref().len() as u64
            };
            let pos = self.bytes.position() as usize;
            Ok(&self.bytes.get_ref()[pos..end as usize])
        }

        fn consume(&mut self, n: usize) {
            self.bytes.set_position(self.bytes.position() + n as u64);
        }
    }

    #[test]
    fn an_interruption_between_members_loses_nothing() {
        let first = gz(b"one\n");
        let at = first.len() as u64;
        let bytes = [first, gz(b"two\n")].concat();
        let input = InterruptedAt {
            bytes: Cursor::new(bytes),
            at,
        };
        assert_eq!(read_from(Box::new(input)), (b"one\ntwo\n".to_vec(), None));
    }

    #[test]
    fn members_read_in_turn_and_trailing_garbage_is_named_after_them() {
        assert_eq!(read(gz(b"one\n")), (b"one\n".to_vec(), None));
        let two = [gz(b"one\n"), gz(b"two\n")].concat();
        assert_eq!(read(two.clone()), (b"one\ntwo\n".to_vec(), None));
        let garbage = [two, b"JUNK".to_vec()].concat();
        let (text, e) = read(garbage);
        assert_eq!(text, b"one\ntwo\n");
        assert_eq!(e.as_deref(), Some(TRAILING_GARBAGE));
        // Zero bytes up to the end are padding; zeros and then anything else, garbage.
        let padded = [gz(b"one\n"), vec![0; 5000]].concat();
        assert_eq!(read(padded.clone()), (b"one\n".to_vec(), None));
        let (_, e) = read([padded, b"x".to_vec()].concat());
        assert_eq!(e.as_deref(), Some(TRAILING_GARBAGE));
        // A second member cut short is the decoder's error, after the first member.
        let mut cut = [gz(b"one\n"), gz(b"two\n")].concat();
        cut.truncate(cut.len() - 10);
        let (text, e) = read(cut);
        assert!(text.starts_with(b"one\n"));
        assert!(e.is_some_and(|e| e != TRAILING_GARBAGE));
    }
}
