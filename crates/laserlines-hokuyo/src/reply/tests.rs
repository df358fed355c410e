//! Worked examples of the specification and damaged messages.

use super::*;
use crate::codec::Encoding;

#[test]
fn a_qt_reply_parses() {
    let r = Reply::parse(b"QT\n00P\n\n").unwrap();
    assert_eq!(r.echo, b"QT");
    assert!(r.status.is_ok());
    assert_eq!(r.data_line_count(), 0);
}

// The PP reply lines the specification prints for the URG-04LX, with their checks.
#[test]
fn the_specifications_pp_reply_gives_its_parameters() {
    let msg = b"PP\n00P\nDMIN:20;4\nDMAX:5600;_\nAMIN:44;7\nAMAX:725;o\nAFRT:384;6\nSCAN:600;e\n\n";
    let r = Reply::parse_unchecked(msg).unwrap();
    let info = r.info().unwrap();
    assert_eq!(info[0], ("DMIN".to_owned(), "20".to_owned()));
    assert_eq!(info[5], ("SCAN".to_owned(), "600".to_owned()));
    // A wrong check character is reported with its line.
    let bad = b"PP\n00P\nDMIN:20;5\n\n";
    let e = Reply::parse_unchecked(bad).unwrap().info().unwrap_err();
    assert!(matches!(e, ReplyError::Checksum { line: 3, .. }), "{e}");
}

// A GD reply of three steps, 3-character encoding, built by hand from the
// specification: echo, "00P", time stamp + check, data + check, empty line.
#[test]
fn a_hand_made_gd_reply_decodes() {
    // Time stamp 16,000,000 ms = "m2@0"; ranges 5432 ("1Dh"), 1234 ("01B"... 3 chars:
    // 1234 = 0b000000_010011_010010 = "0CB"), 7 ("007": an error code).
    let mut msg = b"GD0044004601\n00P\n".to_vec();
    msg.extend_from_slice(b"m2@0");
    msg.push(check_char(b"m2@0"));
    msg.push(b'\n');
    let data = b"1Dh0CB007";
    msg.extend_from_slice(data);
    msg.push(check_char(data));
    msg.extend_from_slice(b"\n\n");
    let r = Reply::parse(&msg).unwrap();
    let mut v = Vec::new();
    let t = r.scan_into(Encoding::Three, 3, &mut v).unwrap();
    assert_eq!(t, 16_000_000);
    assert_eq!(v, vec![5432, 1234, 7]);
    // Asking for four values: the data are short.
    assert!(matches!(
        r.scan_into(Encoding::Three, 4, &mut v),
        Err(ReplyError::Length {
            expected: 12,
            found: 9,
            ..
        })
    ));
}

#[test]
fn values_straddling_line_ends_decode() {
    // 2 values of 3 chars split as "1D" | "h0CB".
    let mut msg = b"MD0044004501000\n99b\n".to_vec();
    for line in [&b"0000"[..], b"1D", b"h0CB"] {
        msg.extend_from_slice(line);
        msg.push(check_char(line));
        msg.push(b'\n');
    }
    msg.push(b'\n');
    let r = Reply::parse(&msg).unwrap();
    assert_eq!(r.status, Status::Scip2(*b"99"));
    let mut v = Vec::new();
    assert_eq!(r.scan_into(Encoding::Three, 2, &mut v), Ok(0));
    assert_eq!(v, vec![5432, 1234]);
}

#[test]
fn damaged_messages_are_named() {
    assert_eq!(Reply::parse(b"QT\n00P\n"), Err(ReplyError::Unterminated));
    assert_eq!(Reply::parse(b"QT\n\n"), Err(ReplyError::MissingStatus));
    assert!(matches!(
        Reply::parse(b"QT\n00Q\n\n"),
        Err(ReplyError::Checksum { line: 2, .. })
    ));
    assert!(matches!(
        Reply::parse(b"QT\n00PP\n\n"),
        Err(ReplyError::BadStatusLine { .. })
    ));
    assert!(matches!(
        Reply::parse(b"GD\n00P\n0000!\n\n"),
        Err(ReplyError::Checksum { line: 3, .. })
    ));
    // A data line cut short before the last one is told from a corrupted one.
    let mut msg = b"MD0044004501000\n99b\n".to_vec();
    for line in [&b"0000"[..], b"1D", b"h0CB"] {
        msg.extend_from_slice(line);
        msg.push(check_char(line));
        msg.push(b'\n');
    }
    msg.push(b'\n');
    let r = Reply::parse_unchecked(&msg).unwrap();
    assert!(matches!(
        r.check_scan_layout(Encoding::Three, 2),
        Err(ReplyError::LineLength {
            line: 4,
            found: 2,
            ..
        })
    ));
    assert!(r.verify_data().is_ok());
    assert_eq!(
        Reply::parse(b"SCIP2.0\n0\n\n").unwrap().status,
        Status::Single(b'0')
    );
}

#[test]
fn the_framer_cuts_at_double_line_feeds_across_pushes() {
    let mut f = Framer::new();
    f.push(b"QT\n00");
    assert_eq!(f.next_message(), None);
    f.push(b"P\n");
    assert_eq!(f.next_message(), None);
    f.push(b"\nBM\n00P\n\nVV");
    assert_eq!(f.next_message().unwrap(), b"QT\n00P\n\n");
    assert_eq!(f.next_message().unwrap(), b"BM\n00P\n\n");
    assert_eq!(f.next_message(), None);
    assert_eq!(f.pending(), 2);
    f.push(&vec![b'x'; MAX_MESSAGE + 1]);
    assert_eq!(f.next_message(), None);
    assert_eq!(f.overflows(), 1);
    assert_eq!(f.pending(), 0);
}
