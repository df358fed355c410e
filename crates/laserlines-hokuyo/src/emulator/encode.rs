//! The sensor's side of the codec: replies and scan messages as bytes, and the damage the
//! fault injection does to them.

use crate::codec::{Encoding, check_char, encode_into};
use crate::reply::DATA_LINE;

/// Appends `status` with its check character and a line feed.
fn push_status(out: &mut Vec<u8>, status: &[u8; 2]) {
    out.extend_from_slice(status);
    out.push(check_char(status));
    out.push(b'\n');
}

/// A reply without data: echo, status, end.
#[must_use]
pub fn simple_reply(echo: &[u8], status: &[u8; 2]) -> Vec<u8> {
    let mut out = Vec::with_capacity(echo.len() + 6);
    out.extend_from_slice(echo);
    out.push(b'\n');
    push_status(&mut out, status);
    out.push(b'\n');
    out
}

/// A reply whose data lines are `text` + check character each (`TM1`, `%ST`).
#[must_use]
pub fn data_reply(echo: &[u8], status: &[u8; 2], lines: &[&[u8]]) -> Vec<u8> {
    let mut out = Vec::with_capacity(echo.len() + 16);
    out.extend_from_slice(echo);
    out.push(b'\n');
    push_status(&mut out, status);
    for l in lines {
        out.extend_from_slice(l);
        out.push(check_char(l));
        out.push(b'\n');
    }
    out.push(b'\n');
    out
}

/// An information reply (`VV`, `PP`, `II`): `LABEL:VALUE;C` lines, the check character
/// over `LABEL:VALUE`.
#[must_use]
pub fn info_reply(echo: &[u8], pairs: &[(&str, String)]) -> Vec<u8> {
    let mut out = Vec::with_capacity(256);
    out.extend_from_slice(echo);
    out.push(b'\n');
    push_status(&mut out, b"00");
    for (k, v) in pairs {
        let text = format!("{k}:{v}");
        out.extend_from_slice(text.as_bytes());
        out.push(b';');
        out.push(check_char(text.as_bytes()));
        out.push(b'\n');
    }
    out.push(b'\n');
    out
}

/// A scan message: echo, status, the 4-character time stamp, the values in lines of 64
/// characters, each line with its check character, and the empty line.
#[must_use]
pub fn scan_message(
    echo: &[u8],
    status: &[u8; 2],
    timestamp: u32,
    values: &[u32],
    encoding: Encoding,
) -> Vec<u8> {
    let mut data = Vec::with_capacity(values.len() * encoding.chars());
    for &v in values {
        encode_into(v.min(encoding.max_value()), encoding, &mut data);
    }
    let mut out = Vec::with_capacity(echo.len() + data.len() + data.len() / DATA_LINE * 2 + 16);
    out.extend_from_slice(echo);
    out.push(b'\n');
    push_status(&mut out, status);
    let mut stamp = Vec::with_capacity(4);
    encode_into(timestamp, Encoding::Four, &mut stamp);
    out.extend_from_slice(&stamp);
    out.push(check_char(&stamp));
    out.push(b'\n');
    for chunk in data.chunks(DATA_LINE) {
        out.extend_from_slice(chunk);
        out.push(check_char(chunk));
        out.push(b'\n');
    }
    out.push(b'\n');
    out
}

/// The byte range of line `k` (0-based) of a message, without its line feed.
fn line_range(msg: &[u8], k: usize) -> Option<std::ops::Range<usize>> {
    let mut start = 0;
    for _ in 0..k {
        start += msg[start..].iter().position(|&b| b == b'\n')? + 1;
    }
    let len = msg.get(start..)?.iter().position(|&b| b == b'\n')?;
    Some(start..start + len)
}

/// Gives the first data line of a scan message (line 4) a wrong check character.
pub fn corrupt_check(msg: &mut [u8]) {
    if let Some(r) = line_range(msg, 3).filter(|r| !r.is_empty()) {
        let c = &mut msg[r.end - 1];
        *c = 0x30 + ((c.wrapping_sub(0x30) + 1) & 0x3f);
    }
}

/// Cuts the first data line of a scan message (line 4) short: its last 10 characters,
/// check character included, are lost; the line feed stays.
pub fn cut_line(msg: &mut Vec<u8>) {
    if let Some(r) = line_range(msg, 3) {
        let cut = r.len().min(10);
        msg.drain(r.end - cut..r.end);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reply::{Reply, ReplyError};

    #[test]
    fn scan_messages_parse_back_and_damage_is_told_apart() {
        let values: Vec<u32> = (0..100).map(|i| i * 50).collect();
        let msg = scan_message(
            b"MD0000009901000",
            b"99",
            16_777_215,
            &values,
            Encoding::Three,
        );
        let r = Reply::parse(&msg).unwrap();
        let mut out = Vec::new();
        assert_eq!(r.scan_into(Encoding::Three, 100, &mut out), Ok(16_777_215));
        assert_eq!(out, values);

        let mut bad = msg.clone();
        corrupt_check(&mut bad);
        let r = Reply::parse_unchecked(&bad).unwrap();
        assert!(r.check_scan_layout(Encoding::Three, 100).is_ok());
        assert!(matches!(
            r.verify_data(),
            Err(ReplyError::Checksum { line: 4, .. })
        ));

        let mut cut = msg;
        cut_line(&mut cut);
        let r = Reply::parse_unchecked(&cut).unwrap();
        assert!(matches!(
            r.check_scan_layout(Encoding::Three, 100),
            Err(ReplyError::LineLength {
                line: 4,
                found: 54,
                ..
            })
        ));
    }

    #[test]
    fn info_replies_parse_back() {
        let msg = info_reply(
            b"PP",
            &[("DMIN", "20".to_owned()), ("SCAN", "600".to_owned())],
        );
        assert_eq!(&msg[..], b"PP\n00P\nDMIN:20;4\nSCAN:600;e\n\n");
    }
}
