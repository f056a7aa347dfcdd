//! How a run of the sweep ended ([`Verdict`]) and the class it is drawn and
//! summarised as ([`Class`]).

use super::{StressOptions, StressRun};
use crate::error::Diagnosis;
use crate::stop::StopKind;

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Finished within every tolerance.
    Stable,
    /// Stopped by a guard.
    Guard(Diagnosis),
    /// Finished, but the energy (or angular momentum) error is above tolerance.
    Energy,
    /// Finished, but the final invariants are off the reference.
    Outcome,
    /// The step panicked (a bug: never acceptable).
    Panic(String),
}

impl Verdict {
    /// Whether the run counts as stable.
    pub fn is_stable(&self) -> bool {
        *self == Verdict::Stable
    }

    /// How the run ended, in a few words (tables).
    pub(crate) fn short(&self, o: &StressOptions) -> String {
        match self {
            Verdict::Stable => "stable".into(),
            Verdict::Energy => format!("finished, energy/L error > {} %", o.energy_tol_pct),
            Verdict::Outcome => format!("finished, final state off rk4 > {} %", o.outcome_tol_pct),
            Verdict::Guard(d) => {
                format!("stopped by guard `{}` at step {}", d.kind.short(), d.step)
            }
            Verdict::Panic(_) => "panic".into(),
        }
    }

    /// The map class of the run.
    pub(crate) fn class(&self) -> Class {
        match self {
            Verdict::Stable => Class::Stable,
            Verdict::Energy => Class::EnergyError,
            Verdict::Outcome => Class::OffReference,
            Verdict::Guard(d) => match d.kind {
                StopKind::Overlap => Class::OverlapGuard,
                StopKind::EnergyBlowUp => Class::EnergyGuard,
                StopKind::ScalarSingularity => Class::ScalarPoleGuard,
                StopKind::NonFiniteState
                | StopKind::NonFiniteEnergy
                | StopKind::QuatNormDrift
                | StopKind::DegenerateOrientation
                | StopKind::Interrupted { .. } => Class::BrokenStateGuard,
            },
            Verdict::Panic(_) => Class::Panic,
        }
    }

    /// The text in the run's map cell: its class's, except that the broken
    /// state class tells a non-finite state (`NaN`) from a drifted or
    /// degenerate orientation (`|q|`).
    pub(crate) fn cell_text(&self) -> &'static str {
        match self {
            Verdict::Guard(d)
                if matches!(
                    d.kind,
                    StopKind::QuatNormDrift
                        | StopKind::DegenerateOrientation
                        | StopKind::Interrupted { .. }
                ) =>
            {
                "|q|"
            }
            v => v.class().cell(),
        }
    }

    /// How the instability was detected, for the tables.
    pub(crate) fn detection(&self, r: &StressRun, o: &StressOptions) -> String {
        match self {
            Verdict::Stable => String::new(),
            Verdict::Energy => format!(
                "accuracy threshold: {} error {:.3} % > {} %",
                if r.momentum_err_pct > r.energy_err_pct {
                    "angular momentum"
                } else {
                    "energy"
                },
                r.energy_err_pct.max(r.momentum_err_pct),
                o.energy_tol_pct
            ),
            Verdict::Outcome => format!(
                "accuracy threshold: final state off the reference by {:.3} % > {} %",
                r.outcome_err_pct, o.outcome_tol_pct
            ),
            Verdict::Guard(d) => format!(
                "guard `{}`: {} = {:.3e} > {:.3e} at t = {:.3e} s",
                d.kind.short(),
                d.quantity(),
                d.value,
                d.limit,
                d.t
            ),
            Verdict::Panic(m) => format!("PANIC: {m}"),
        }
    }
}

/// A class of the stability map: one legend entry, its colour, the text in
/// its cells and its name in the summarised detections.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Class {
    Stable,
    /// Finished, energy (or angular momentum) error above tolerance.
    EnergyError,
    /// Finished, final state off the reference.
    OffReference,
    OverlapGuard,
    EnergyGuard,
    ScalarPoleGuard,
    /// A non-finite state or a drifted or degenerate orientation.
    BrokenStateGuard,
    Panic,
}

impl Class {
    /// Every class, in legend order.
    pub(crate) const ALL: [Class; 8] = [
        Class::Stable,
        Class::EnergyError,
        Class::OffReference,
        Class::OverlapGuard,
        Class::EnergyGuard,
        Class::ScalarPoleGuard,
        Class::BrokenStateGuard,
        Class::Panic,
    ];

    /// Position in [`Class::ALL`] (the map's legend index).
    pub(crate) fn index(self) -> usize {
        self as usize
    }

    /// The legend entry.
    pub(crate) fn label(self) -> &'static str {
        match self {
            Class::Stable => "stable",
            Class::EnergyError => "finished, energy/L error > tol (E)",
            Class::OffReference => "finished, final state wrong (out)",
            Class::OverlapGuard => "guard: overlap > 0.2 D (ovl)",
            Class::EnergyGuard => "guard: energy error > 10 % (E>10%)",
            Class::ScalarPoleGuard => "guard: scalar tan pole (tan)",
            Class::BrokenStateGuard => "guard: non-finite / |q| drift",
            Class::Panic => "panic",
        }
    }

    /// Cell colour (Okabe–Ito where it fits).
    pub(crate) fn colour(self) -> [u8; 3] {
        match self {
            Class::Stable => [0x00, 0x9E, 0x73],
            Class::EnergyError => [0xE6, 0x9F, 0x00],
            Class::OffReference => [0xF0, 0xE4, 0x42],
            Class::OverlapGuard => [0xD5, 0x5E, 0x00],
            Class::EnergyGuard => [0xCC, 0x79, 0xA7],
            Class::ScalarPoleGuard => [0x56, 0xB4, 0xE9],
            Class::BrokenStateGuard => [0x00, 0x72, 0xB2],
            Class::Panic => [0x00, 0x00, 0x00],
        }
    }

    /// The short text in a cell of this class (see [`Verdict::cell_text`]).
    pub(crate) fn cell(self) -> &'static str {
        match self {
            Class::Stable => "",
            Class::EnergyError => "E",
            Class::OffReference => "out",
            Class::OverlapGuard => "ovl",
            Class::EnergyGuard => "E>10%",
            Class::ScalarPoleGuard => "tan",
            Class::BrokenStateGuard => "NaN",
            Class::Panic => "PANIC",
        }
    }

    /// A few words naming the class, for the summarised detections.
    pub(crate) fn words(self, o: &StressOptions) -> String {
        match self {
            Class::Stable => "stable".into(),
            Class::EnergyError => format!("energy/L error > {} %", o.energy_tol_pct),
            Class::OffReference => format!("final state off rk4 > {} %", o.outcome_tol_pct),
            Class::OverlapGuard => "overlap guard".into(),
            Class::EnergyGuard => "energy guard".into(),
            Class::ScalarPoleGuard => "scalar tan-pole guard".into(),
            Class::BrokenStateGuard => "non-finite / |q| guard".into(),
            Class::Panic => "PANIC".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_lists_each_class_once_at_its_index() {
        for (i, c) in Class::ALL.iter().enumerate() {
            assert_eq!(c.index(), i, "{c:?}");
        }
    }

    /// The map tells classes apart by colour and legend text only.
    #[test]
    fn classes_have_distinct_colours_and_labels() {
        for a in Class::ALL {
            for b in Class::ALL.into_iter().filter(|&b| b != a) {
                assert_ne!(a.colour(), b.colour(), "{a:?} {b:?}");
                assert_ne!(a.label(), b.label(), "{a:?} {b:?}");
            }
        }
    }
}
