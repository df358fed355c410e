//! The SCIP 2.0 character codec: the check character of a line and the 2-, 3- and
//! 4-character encodings of numbers.
//!
//! Every SCIP 2.0 line the sensor sends ends with a check character: the sum of the line's
//! bytes, its lower 6 bits, plus `0x30`. Numbers are sent 6 bits per character, most
//! significant first, each plus `0x30`: two characters carry 12 bits (ranges of `MS`/`GS`),
//! three carry 18 bits (ranges of `MD`/`GD`), four carry 24 bits (time stamps).

/// The check character of `bytes`: `(sum of the bytes & 0x3f) + 0x30`.
///
/// ```
/// // The status line "00" is sent as "00P".
/// assert_eq!(laserlines_hokuyo::codec::check_char(b"00"), b'P');
/// ```
#[must_use]
pub fn check_char(bytes: &[u8]) -> u8 {
    let sum = bytes
        .iter()
        .fold(0u32, |s, &b| s.wrapping_add(u32::from(b)));
    (sum & 0x3f) as u8 + 0x30
}

/// How many characters encode one number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Encoding {
    /// 2 characters, 12 bits (0..=4095): `MS`, `GS`.
    Two,
    /// 3 characters, 18 bits (0..=262143): `MD`, `GD`.
    Three,
    /// 4 characters, 24 bits: time stamps.
    Four,
}

impl Encoding {
    /// Characters per number.
    #[must_use]
    pub const fn chars(self) -> usize {
        match self {
            Self::Two => 2,
            Self::Three => 3,
            Self::Four => 4,
        }
    }

    /// The largest number the encoding carries.
    #[must_use]
    pub const fn max_value(self) -> u32 {
        (1 << (6 * self.chars() as u32)) - 1
    }
}

/// A character outside the encoding's range `0x30..=0x6f`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "character {byte:#04x} at position {position} is not a SCIP number character (0x30..=0x6f)"
)]
pub struct DecodeError {
    /// Position of the character in the slice decoded.
    pub position: usize,
    /// The character.
    pub byte: u8,
}

/// Decodes one number of `chars.len()` characters (1 to 5; longer input overflows no
/// further than `u32` allows, the caller chooses the length).
///
/// # Errors
/// [`DecodeError`] for a character below `0x30` or above `0x6f`.
///
/// ```
/// use laserlines_hokuyo::codec::decode;
/// assert_eq!(decode(b"CB"), Ok(1234));        // the protocol's 2-character example
/// assert_eq!(decode(b"1Dh"), Ok(5432));       // 3-character example
/// assert_eq!(decode(b"m2@0"), Ok(16_000_000)); // 4-character example
/// ```
pub fn decode(chars: &[u8]) -> Result<u32, DecodeError> {
    let mut value = 0u32;
    for (position, &byte) in chars.iter().enumerate() {
        let digit = byte.wrapping_sub(0x30);
        if digit > 0x3f {
            return Err(DecodeError { position, byte });
        }
        value = (value << 6) | u32::from(digit);
    }
    Ok(value)
}

/// Appends `value` encoded in `encoding` to `out`; bits above the encoding's width are
/// dropped (callers clamp first: see [`Encoding::max_value`]).
pub fn encode_into(value: u32, encoding: Encoding, out: &mut Vec<u8>) {
    let n = encoding.chars();
    for i in (0..n).rev() {
        out.push(((value >> (6 * i)) & 0x3f) as u8 + 0x30);
    }
}

/// `value` encoded in `encoding`, as a new vector.
#[must_use]
pub fn encode(value: u32, encoding: Encoding) -> Vec<u8> {
    let mut out = Vec::with_capacity(encoding.chars());
    encode_into(value, encoding, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    // Worked examples of the SCIP 2.0 specification (section "Data encoding and decoding").
    #[test]
    fn the_specifications_examples_encode_and_decode() {
        assert_eq!(encode(1234, Encoding::Two), b"CB");
        assert_eq!(encode(5432, Encoding::Three), b"1Dh");
        assert_eq!(encode(16_000_000, Encoding::Four), b"m2@0");
        assert_eq!(decode(b"CB"), Ok(1234));
        assert_eq!(decode(b"1Dh"), Ok(5432));
        assert_eq!(decode(b"m2@0"), Ok(16_000_000));
    }

    // The status lines and parameter lines the specification prints with their checks.
    #[test]
    fn check_characters_of_the_specifications_lines() {
        assert_eq!(check_char(b"00"), b'P');
        assert_eq!(check_char(b"99"), b'b');
        // PP reply lines: the check covers "LABEL:VALUE", not the ';'.
        assert_eq!(check_char(b"DMIN:20"), b'4');
        assert_eq!(check_char(b"DMAX:5600"), b'_');
        assert_eq!(check_char(b"AFRT:384"), b'6');
        assert_eq!(check_char(b"AMIN:44"), b'7');
        assert_eq!(check_char(b"AMAX:725"), b'o');
        assert_eq!(check_char(b"SCAN:600"), b'e');
    }

    #[test]
    fn every_value_round_trips_and_bad_characters_are_named() {
        for enc in [Encoding::Two, Encoding::Three, Encoding::Four] {
            for v in [0, 1, 19, 20, 63, 64, 4095, enc.max_value()] {
                let v = v.min(enc.max_value());
                assert_eq!(decode(&encode(v, enc)), Ok(v));
            }
        }
        assert_eq!(
            decode(b"0p"),
            Err(DecodeError {
                position: 1,
                byte: b'p'
            })
        );
        assert_eq!(
            decode(b"\n0"),
            Err(DecodeError {
                position: 0,
                byte: b'\n'
            })
        );
    }
}
