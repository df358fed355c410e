//! Gzip input of one or more members (as `cat a.gz b.gz > ab.gz` makes), read member by
//! member, so that bytes after the last member that do not start another (trailing garbage,
//! which `gzip -d` warns of and drops) end the input with an error that says so, after every
//! byte of the members before them.

use std::io::{self, BufRead, Read};

use flate2::bufread::GzDecoder;

use crate::reader::Input;

/// The first byte of every gzip member.
const GZIP_ID1: u8 = 0x1f;
/// The second byte of every gzip member.
const GZIP_ID2: u8 = 0x8b;

/// The error of bytes after the last member that are not another member.
pub const TRAILING_GARBAGE: &str = "bytes after the end of the gzip data that do not start \
     another gzip member (trailing garbage; everything before them was read)";

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
            let n = decoder.read(buf)?;
            if n > 0 || buf.is_empty() {
                return Ok(n);
            }
            // The member ended: the bytes after it end the input or start the next member.
            let Some(mut rest) = self.decoder.take().map(GzDecoder::into_inner) else {
                break;
            };
            if starts_member(&mut rest)? {
                self.decoder = Some(GzDecoder::new(rest));
            }
        }
        Ok(0)
    }
}

/// True when `rest` starts another member, false when it is empty; an error for anything
/// else.
fn starts_member(rest: &mut Input) -> io::Result<bool> {
    let head = rest.fill_buf()?;
    let member = match head {
        [] => return Ok(false),
        [GZIP_ID1, GZIP_ID2, ..] => true,
        // The second byte beyond the buffer: the member's header says the rest.
        [GZIP_ID1] => true,
        _ => false,
    };
    if member {
        Ok(true)
    } else {
        Err(io::Error::new(io::ErrorKind::InvalidData, TRAILING_GARBAGE))
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
        let mut m = Members::new(Box::new(Cursor::new(bytes)));
        let mut out = Vec::new();
        let mut buf = [0u8; 7];
        loop {
            match m.read(&mut buf) {
                Ok(0) => return (out, None),
                Ok(n) => out.extend_from_slice(&buf[..n]),
                Err(e) => return (out, Some(e.to_string())),
            }
        }
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
        // A second member cut short is the decoder's error, after the first member.
        let mut cut = [gz(b"one\n"), gz(b"two\n")].concat();
        cut.truncate(cut.len() - 10);
        let (text, e) = read(cut);
        assert!(text.starts_with(b"one\n"));
        assert!(e.is_some_and(|e| e != TRAILING_GARBAGE));
    }
}
