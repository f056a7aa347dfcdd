//! One look per rotator in every figure (`compare`, `converge`, `plot`,
//! `stress`): its palette slot, which picks its colour and marker shape, is
//! its place in the rotator list, so a rotator added to `rotator_list!`
//! gets the next one.

use crate::integrate::rotate::RotatorKind;

/// The palette slot of rotator `k`.
pub(crate) fn rotator_slot(k: RotatorKind) -> usize {
    RotatorKind::SELECTABLE
        .iter()
        .position(|&r| r == k)
        .expect("every rotator is in the list")
}

/// The slot of the rotator a series label names (`pcdm`, `run/pcdm`), if any.
pub(crate) fn slot_of_label(label: &str) -> Option<usize> {
    let name = label.rsplit('/').next().unwrap_or(label);
    RotatorKind::from_name(name).map(rotator_slot)
}
