//! Step 3: radius grouping and merging of touching groups (paper section II-B, ALGORITHM
//! section 2), as connected components of the kept cells.
//!
//! Grouping along a ring and merging groups that touch in a neighbouring ring is computed in
//! one union-find pass over the kept cells: two kept cells are joined when they lie in the same
//! ring at most `1 + group_gap` sectors apart, or in neighbouring rings of the same or of
//! neighbouring sectors (the 8-neighbourhood). Each connected component is one group of the
//! paper's Fig. 4b.

use super::accumulator::{Accumulator, Bin, NONE};
use super::params::HoughSplitParams;

/// Rings up to which [`connect_cells`] looks neighbours up in a table indexed by ring.
const TABLE_RINGS: u32 = 1 << 16;

/// Union-find over the kept cells (the parent of a cell not kept is `NONE`). A root is always
/// the smallest index of its set, so every parent lies before its child:
/// [`Components::flatten`] needs one pass.
#[derive(Debug, Default, Clone)]
pub(crate) struct Components {
    pub(crate) parent: Vec<u32>,
    /// Per ring: the last sector (plus one, 0 for none) with a kept cell in that ring, and
    /// that cell.
    latest: Vec<(u32, u32)>,
}

impl Components {
    /// Every kept cell of `bins` its own set; the others `NONE`.
    fn reset(&mut self, bins: &[Bin]) {
        self.parent.clear();
        self.parent.extend(
            bins.iter()
                .enumerate()
                .map(|(c, b)| if b.kept { c as u32 } else { NONE }),
        );
    }

    #[inline]
    pub(crate) fn find(&mut self, mut x: usize) -> usize {
        loop {
            let p = self.parent[x] as usize;
            if p == x {
                return x;
            }
            let grand = self.parent[p];
            self.parent[x] = grand;
            x = grand as usize;
        }
    }

    #[inline(always)]
    pub(crate) fn same(&mut self, a: usize, b: usize) -> bool {
        self.parent[a] == self.parent[b] || self.find(a) == self.find(b)
    }

    #[inline(always)]
    pub(crate) fn union(&mut self, a: usize, b: usize) {
        // The usual case: already joined through a common parent.
        if self.parent[a] == self.parent[b] {
            return;
        }
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // Smaller index becomes the root: roots are then deterministic and in scan order.
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi] = lo as u32;
        }
    }

    /// Points every kept cell at its root directly (parents come before their children).
    pub(crate) fn flatten(&mut self) {
        for c in 0..self.parent.len() {
            let p = self.parent[c];
            if p != NONE && (p as usize) < c {
                self.parent[c] = self.parent[p as usize];
            }
        }
    }
}

/// Joins touching kept cells (grouping along rings and merging across rings), and leaves
/// every cell pointing at its component's root.
///
/// Sector by sector, each kept cell looks up the kept cells it touches in earlier sectors
/// in a table of the latest kept cell of each ring: the one in its own ring (when at most
/// `1 + group_gap` sectors back: any other kept cell of that ring within reach is already
/// joined to it) and those in the neighbouring rings (when in the sector just before).
pub(crate) fn connect_cells(acc: &Accumulator, p: &HoughSplitParams, uf: &mut Components) {
    let bins = &acc.bins[..];
    uf.reset(bins);
    let top = acc.top_ring;
    if top >= TABLE_RINGS {
        connect_by_merging(acc, p, uf);
        uf.flatten();
        return;
    }
    let reach = p.group_gap.saturating_add(1);
    let mut latest = std::mem::take(&mut uf.latest);
    latest.clear();
    latest.resize(top as usize + 2, (0, 0));
    let starts = &acc.sector_start[..];
    for k in 0..starts.len().saturating_sub(1) {
        let here = starts[k] as usize..starts[k + 1] as usize;
        let stamp = k as u32 + 1;
        for c in here.clone() {
            let cell = bins[c];
            if !cell.kept {
                continue;
            }
            let r = cell.ring as usize;
            // Same sector: the neighbouring ring below.
            if c > here.start && bins[c - 1].kept && cell.ring - bins[c - 1].ring <= 1 {
                uf.union(c - 1, c);
            }
            // The sector before: the neighbouring rings. (A cell of this sector in the ring
            // below has replaced the entry there; it is joined to this cell and to the earlier
            // one in its ring already.)
            let (below, above) = (latest[r.saturating_sub(1)], latest[r + 1]);
            if below.0 == stamp - 1 && below.0 != 0 {
                uf.union(c, below.1 as usize);
            }
            if above.0 == stamp - 1 && above.0 != 0 {
                uf.union(c, above.1 as usize);
            }
            // The same ring, up to `1 + group_gap` sectors before.
            let (s, o) = latest[r];
            if s != 0 && ((stamp - s) as usize) <= reach {
                uf.union(c, o as usize);
            }
            latest[r] = (stamp, c as u32);
        }
    }
    uf.latest = latest;
    uf.flatten();
}

/// [`connect_cells`] for cells in rings beyond the table: each sector's cells merged with
/// those of the sectors before it, both in ring order.
fn connect_by_merging(acc: &Accumulator, p: &HoughSplitParams, uf: &mut Components) {
    let bins = &acc.bins[..];
    let starts = &acc.sector_start[..];
    for k in 0..starts.len().saturating_sub(1) {
        let here = starts[k] as usize..starts[k + 1] as usize;
        // Same sector: neighbouring rings.
        for c in here.start.saturating_add(1)..here.end {
            let (a, b) = (bins[c - 1], bins[c]);
            if a.kept && b.kept && b.ring - a.ring <= 1 {
                uf.union(c - 1, c);
            }
        }
        // Earlier sectors: the neighbouring one in the 8-neighbourhood, farther ones (up to the
        // grouping gap) along the same ring only.
        for back in 1..=p.group_gap.saturating_add(1).min(k) {
            let there = starts[k - back] as usize..starts[k - back + 1] as usize;
            let reach = u32::from(back == 1);
            let mut lo = there.start;
            for c in here.clone() {
                let cell = bins[c];
                if !cell.kept {
                    continue;
                }
                while lo < there.end && bins[lo].ring + reach < cell.ring {
                    lo += 1;
                }
                let mut o = lo;
                while o < there.end && bins[o].ring <= cell.ring + reach {
                    if bins[o].kept {
                        uf.union(c, o);
                    }
                    o += 1;
                }
            }
        }
    }
}
