//! The box as a static `.vtp` outline: its 8 corners and 12 edges as
//! `VTK_LINE` cells (exact, Float64).

use super::xml::{polydata, Array, Data, PolyPiece};
use crate::scenario::Walls;

/// The outline's `.vtp` bytes.
pub(crate) fn box_bytes(w: &Walls) -> Vec<u8> {
    let (lo, hi) = (w.min, w.max);
    let corner = |k: usize| {
        [
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        ]
    };
    let points: Vec<f64> = (0..8).flat_map(corner).collect();
    // Corners differing in one bit are joined by an edge.
    let mut connectivity = vec![];
    for a in 0..8i32 {
        for bit in [1, 2, 4] {
            if a & bit == 0 {
                connectivity.extend([a, a | bit]);
            }
        }
    }
    let offsets: Vec<i32> = (1..=12).map(|k| 2 * k).collect();
    let piece = PolyPiece {
        field: vec![],
        points: Array::new("Points", 3, Data::F64(&points)),
        cells: vec![],
        lines: [
            Array::new("connectivity", 1, Data::I32(&connectivity)),
            Array::new("offsets", 1, Data::I32(&offsets)),
        ],
        n_points: 8,
        n_lines: 12,
    };
    polydata(&piece, "fibresim box: the walls of [box]")
}
