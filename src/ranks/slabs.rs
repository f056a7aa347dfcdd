//! The decomposition: K slabs along one axis, cut by fibre count, and the
//! ghosts each rank needs. A pure function of the centres, so every rank
//! computes the same decomposition from the same (gathered) states.

use glam::DVec3;

/// Who owns which body and which bodies each rank sees as ghosts.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Slabs {
    /// The cut axis (0, 1, 2 for x, y, z).
    pub axis: usize,
    /// Owner rank of each body.
    pub owner: Vec<u32>,
    /// Per rank, the bodies it owns, ascending.
    pub owned: Vec<Vec<u32>>,
    /// Per rank, the bodies of other ranks within the ghost width of its
    /// slab, ascending.
    pub ghosts: Vec<Vec<u32>>,
}

impl Slabs {
    /// Cut the `centres` into `ranks` slabs along the axis of largest
    /// centre spread (a bed settled at the bottom of a tall box is cut
    /// through its own height, not the box's), each slab holding
    /// `⌊(r+1)N/K⌋ − ⌊rN/K⌋` bodies in order of that coordinate (ties by
    /// index); ghosts of rank r are the other ranks' bodies whose centre
    /// is within `width` of r's slab along the axis.
    pub fn new(centres: &[DVec3], ranks: usize, width: f64) -> Self {
        let n = centres.len();
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for c in centres {
            lo = lo.min(*c);
            hi = hi.max(*c);
        }
        let spread = hi - lo;
        let axis = if spread.x >= spread.y && spread.x >= spread.z {
            0
        } else if spread.y >= spread.z {
            1
        } else {
            2
        };
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.sort_unstable_by(|&i, &j| {
            centres[i as usize][axis]
                .total_cmp(&centres[j as usize][axis])
                .then(i.cmp(&j))
        });
        let mut owner = vec![0u32; n];
        let mut owned = vec![Vec::new(); ranks];
        let mut bounds = vec![(f64::INFINITY, f64::NEG_INFINITY); ranks];
        for r in 0..ranks {
            let chunk = &order[r * n / ranks..(r + 1) * n / ranks];
            for &i in chunk {
                owner[i as usize] = r as u32;
            }
            if let (Some(&a), Some(&b)) = (chunk.first(), chunk.last()) {
                bounds[r] = (centres[a as usize][axis], centres[b as usize][axis]);
            }
            owned[r] = chunk.to_vec();
            owned[r].sort_unstable();
        }
        let mut ghosts = vec![Vec::new(); ranks];
        for (i, c) in centres.iter().enumerate() {
            let x = c[axis];
            for (r, &(a, b)) in bounds.iter().enumerate() {
                if owner[i] as usize != r && x >= a - width && x <= b + width {
                    ghosts[r].push(i as u32);
                }
            }
        }
        Slabs {
            axis,
            owner,
            owned,
            ghosts,
        }
    }

    /// The bodies rank `r` holds current states of: its own and its
    /// ghosts, ascending (so local order is global order).
    pub fn local(&self, r: usize) -> Vec<u32> {
        let mut l: Vec<u32> = self.owned[r]
            .iter()
            .chain(&self.ghosts[r])
            .copied()
            .collect();
        l.sort_unstable();
        l
    }

    /// The bodies `from` owns that are ghosts of `to`, ascending: what
    /// `from` sends `to` every step.
    pub fn sends(&self, from: usize, to: usize) -> Vec<u32> {
        self.ghosts[to]
            .iter()
            .copied()
            .filter(|&i| self.owner[i as usize] as usize == from)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A column of bodies at the bottom of a tall box: cut through the
    /// column's height, with equal counts.
    #[test]
    fn cuts_by_count_along_the_longest_spread() {
        let centres: Vec<DVec3> = (0..10)
            .map(|i| DVec3::new(0.01 * (i % 2) as f64, 0.0, 0.1 * i as f64))
            .collect();
        let s = Slabs::new(&centres, 3, 0.15);
        assert_eq!(s.axis, 2);
        assert_eq!(
            s.owned,
            vec![vec![0, 1, 2], vec![3, 4, 5], vec![6, 7, 8, 9]]
        );
        // Rank 1's slab is z ∈ [0.3, 0.5]: ghosts within 0.15 of it.
        assert_eq!(s.ghosts[1], vec![2, 6]);
        assert_eq!(s.sends(2, 1), vec![6]);
        assert_eq!(s.local(1), vec![2, 3, 4, 5, 6]);
        assert_eq!(s.owner[9], 2);
    }
}
