//! Counts of what a reader skipped, by reason, for the summary.

use std::fmt;

/// Counts of skipped records by reason, in the order the reasons first occurred.
///
/// A [`crate::ScanReader`] counts every record it did not produce: each bad record it
/// returned as an error (under [`crate::ReadError::reason`]) and anything a format skips by
/// design. A failed read of the input ends the reading and is not counted here. The
/// caller may add its own reasons (e.g. scans it dropped) with [`SkipCounts::add`].
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SkipCounts {
    counts: Vec<(String, u64)>,
}

impl SkipCounts {
    /// No skips.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Counts one more skip for `reason`.
    pub fn add(&mut self, reason: &str) {
        self.add_n(reason, 1);
    }

    /// Counts `n` more skips for `reason`.
    pub fn add_n(&mut self, reason: &str, n: u64) {
        if n == 0 {
            return;
        }
        if let Some(entry) = self.counts.iter_mut().find(|(r, _)| r == reason) {
            entry.1 += n;
        } else {
            self.counts.push((reason.to_owned(), n));
        }
    }

    /// Adds every count of `other`.
    pub fn merge(&mut self, other: &Self) {
        for (reason, n) in &other.counts {
            self.add_n(reason, *n);
        }
    }

    /// The count for one reason (0 when it never occurred).
    #[must_use]
    pub fn get(&self, reason: &str) -> u64 {
        self.counts
            .iter()
            .find(|(r, _)| r == reason)
            .map_or(0, |(_, n)| *n)
    }

    /// Total number of skips.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.counts.iter().map(|(_, n)| n).sum()
    }

    /// True when nothing was skipped.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.counts.is_empty()
    }

    /// `(reason, count)` pairs in the order the reasons first occurred.
    pub fn iter(&self) -> impl Iterator<Item = (&str, u64)> {
        self.counts.iter().map(|(r, n)| (r.as_str(), *n))
    }
}

/// `none`, or `3 × malformed JSON, 1 × invalid scan` (a count and its reason, which is
/// singular: `2 × malformed record`).
impl fmt::Display for SkipCounts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.counts.is_empty() {
            return f.write_str("none");
        }
        for (i, (reason, n)) in self.counts.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{n} × {reason}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_keep_first_occurrence_order() {
        let mut s = SkipCounts::new();
        assert_eq!(s.to_string(), "none");
        s.add("b");
        s.add("a");
        s.add_n("b", 2);
        s.add_n("c", 0);
        assert_eq!(s.get("b"), 3);
        assert_eq!(s.get("c"), 0);
        assert_eq!(s.total(), 4);
        assert_eq!(s.to_string(), "3 × b, 1 × a");
        let mut t = SkipCounts::new();
        t.add("a");
        t.merge(&s);
        assert_eq!(t.to_string(), "2 × a, 3 × b");
    }
}
