//! The order in which `replicate` numbers its bodies: along a
//! space-filling (Morton, or Z-order) curve through the box, so that bodies
//! near in space are near in the body file and so in memory. The pair loop
//! reads each candidate's partner by its index: in a bed numbered at random
//! (as placement and settling leave it) that read goes anywhere in the
//! state, in a bed numbered along the curve mostly to its neighbours' cache
//! lines, which matters once the state outgrows the caches (10⁵ fibres and
//! more). LAMMPS sorts its atoms spatially for the same reason
//! (`atom_modify sort`). The engine keeps the order it is given (its sums
//! follow it, so a reordered bed is another run at the rounding), and
//! `generate` and `settle` keep theirs, so the beds that scripts made
//! before are made again bit for bit.

use crate::body::BodyState;
use glam::DVec3;

/// Bits per axis of the curve's cells: 2²¹ cells a side, 63 bits a key.
const BITS: u32 = 21;

/// The indices of `states` in the order of their centres along the Morton
/// curve through the box `[lo, hi]` (a centre outside it counts at the
/// nearest face); centres in one cell keep their order.
pub fn space_filling_order(states: &[BodyState], lo: DVec3, hi: DVec3) -> Vec<usize> {
    let cells = f64::from(1u32 << BITS);
    let span = (hi - lo).max(DVec3::splat(f64::MIN_POSITIVE));
    let cell = |x: f64, lo: f64, span: f64| -> u64 {
        // `as` saturates: NaN to 0, beyond the box to the last cell.
        (((x - lo) / span * cells) as u64).min((1 << BITS) - 1)
    };
    let mut keyed: Vec<(u64, usize)> = states
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let key = spread(cell(s.x.x, lo.x, span.x))
                | spread(cell(s.x.y, lo.y, span.y)) << 1
                | spread(cell(s.x.z, lo.z, span.z)) << 2;
            (key, i)
        })
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// The low 21 bits of `v` spread to every third bit (bit k to bit 3k).
fn spread(v: u64) -> u64 {
    (0..BITS).fold(0, |key, b| key | ((v >> b) & 1) << (3 * b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::RotState;
    use glam::DQuat;

    fn at(x: f64, y: f64, z: f64) -> BodyState {
        BodyState {
            x: DVec3::new(x, y, z),
            v: DVec3::ZERO,
            rot: RotState {
                q: DQuat::IDENTITY,
                omega_b: DVec3::ZERO,
            },
        }
    }

    /// The curve's definition on a 2 × 2 × 2 grid: x is the lowest bit of
    /// the key, then y, then z, so the octants come in the order
    /// (0,0,0), (1,0,0), (0,1,0), (1,1,0), (0,0,1), …
    #[test]
    fn octants_follow_the_z_order() {
        let octants: Vec<BodyState> = [7, 2, 5, 0, 3, 6, 1, 4]
            .iter()
            .map(|&k| {
                let c = |bit: i32| if k >> bit & 1 == 1 { 0.75 } else { 0.25 };
                at(c(0), c(1), c(2))
            })
            .collect();
        let order = space_filling_order(&octants, DVec3::ZERO, DVec3::ONE);
        assert_eq!(order, [3, 6, 1, 4, 7, 2, 5, 0]);
    }

    /// Every index once; bodies in one cell (and outside the box, which
    /// counts at its faces) keep their order.
    #[test]
    fn the_order_is_a_permutation_stable_within_a_cell() {
        let states = [
            at(0.5, 0.5, 0.5),
            at(-1.0, 0.0, 0.0),
            at(0.5, 0.5, 0.5),
            at(2.0, 2.0, 2.0),
        ];
        let order = space_filling_order(&states, DVec3::ZERO, DVec3::ONE);
        assert_eq!(order, [1, 0, 2, 3]);
    }

    /// The spread is the bit interleave written out for one value.
    #[test]
    fn spread_puts_bit_k_at_3k() {
        assert_eq!(spread(0b1011), 0b001_000_001_001);
        assert_eq!(spread((1 << BITS) - 1).count_ones(), BITS);
        assert_eq!(spread((1 << BITS) - 1) >> (3 * (BITS - 1)), 1);
    }
}
