//! Reading on past pages of a `.db3` file that SQLite cannot read (a corrupt page, a
//! damaged overflow chain): the messages are read in `id` order, and SQLite finds the page of
//! an id from the table's interior pages, so a query that starts past a damaged leaf page
//! reads the pages after it. [`resume_point`] looks for the first id from which the topic's
//! messages read again.

use rusqlite::{Connection, params};

use super::{ROWS, read_row};

/// True when the first message from id `from` on reads as the reading reads it (its id and
/// topic, and for topic `topic_id` its timestamp and data), or when there is none; false
/// when SQLite fails on the way.
fn reads_from(db: &Connection, topic_id: i64, from: i64) -> bool {
    let read = || -> rusqlite::Result<bool> {
        let mut stmt = db.prepare(ROWS)?;
        let mut rows = stmt.query(params![topic_id, from, 1])?;
        match rows.next()? {
            // A row before `from`: the pages SQLite found it by are damaged.
            Some(row) => Ok(read_row(row, topic_id)?.0 >= from),
            None => Ok(true),
        }
    };
    read().unwrap_or(false)
}

/// Where the reading (of topic `topic_id`) can go on when it failed after message `after`
/// (`i64::MIN` before the first). When the failure came further on than the first row asked
/// for (`at_once` false: the scan through the pages met the damage on its way), `after + 1`
/// itself when a read from there works (SQLite finds a row from the interior pages, which
/// can lead past the damage). Else the smallest id `s > after + 1` from which the next
/// message reads (or from which none is left), found by steps doubling from `after + 1` and
/// then by bisection between the last step that failed and the first that did not. `None`
/// when nothing from `after + 1` on reads (the damage reaches the end of the file, or the
/// table's root). Each resumption goes past the id the reading failed at, so reading ends.
///
/// A read from `s` fails or not by the page SQLite finds `s` on; between a damaged page and
/// the next one, the bisection finds the first id past the damage.
pub(super) fn resume_point(
    db: &Connection,
    topic_id: i64,
    after: i64,
    at_once: bool,
) -> Option<i64> {
    let first = after.checked_add(1)?;
    if !at_once && reads_from(db, topic_id, first) {
        return Some(first);
    }
    // In i128, so that neither the steps nor the differences overflow.
    let (mut bad, mut step) = (i128::from(first), 1i128);
    let mut good = loop {
        let s = (i128::from(first) + step).min(i128::from(i64::MAX));
        if reads_from(db, topic_id, s as i64) {
            break s;
        }
        if s == i128::from(i64::MAX) {
            return None;
        }
        bad = s;
        step *= 2;
    };
    while good - bad > 1 {
        let mid = bad + (good - bad) / 2;
        if reads_from(db, topic_id, mid as i64) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    Some(good as i64)
}

/// The first id passed over after message `after`: the next one, or 1 (rosbag2 numbers its
/// messages from 1) when nothing was read before.
pub(super) fn first_passed(after: i64) -> i64 {
    after.saturating_add(1).max(1)
}

/// The message ids passed over when the reading goes on at `resume` after message `after`:
/// [`first_passed`]`(after) .. resume`.
pub(super) fn passed_over(after: i64, resume: i64) -> u64 {
    u64::try_from(resume.saturating_sub(first_passed(after))).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_passed_over_start_at_one_before_any_message() {
        assert_eq!(passed_over(10, 15), 4);
        assert_eq!(passed_over(10, 11), 0);
        assert_eq!(passed_over(i64::MIN, 8), 7);
        assert_eq!(passed_over(i64::MIN, 1), 0);
        assert_eq!(passed_over(i64::MIN, -5), 0);
    }
}
