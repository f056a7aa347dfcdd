//! Why a run stopped before its end: a typed kind, and the diagnosis that
//! names the step, the body and the quantity past its limit.

use std::path::PathBuf;

/// What stopped a run. Each kind has one message ([`std::fmt::Display`]) and
/// one measured quantity ([`StopKind::quantity`]), the strings written to
/// `summary.json` and stderr.
#[derive(Debug, Clone, PartialEq)]
pub enum StopKind {
    /// A position, velocity, orientation or spin is NaN or infinite.
    NonFiniteState,
    /// A finite state whose energy overflowed.
    NonFiniteEnergy,
    /// A contact overlap beyond the Hertz range (guard `overlap_ratio`).
    Overlap,
    /// The full-budget energy error passed its guard (`energy_error_pct`).
    EnergyBlowUp,
    /// A renormalising scheme produced a zero quaternion.
    DegenerateOrientation,
    /// `| ‖q‖ − 1 |` above its tolerance.
    QuatNormDrift,
    /// The scalar factor `tan(‖ω‖δt/2)` of Eq. 41 at its pole; raised by the
    /// rotator before its step completes.
    ScalarSingularity,
    /// SIGINT: a checkpoint was written at `checkpoint`.
    Interrupted {
        /// The checkpoint written before stopping.
        checkpoint: PathBuf,
        /// The command that continues the run from it.
        resume: String,
    },
}

impl StopKind {
    /// The quantity that crossed its limit.
    pub fn quantity(&self) -> &'static str {
        match self {
            StopKind::NonFiniteState => "state",
            StopKind::NonFiniteEnergy => "energy",
            StopKind::Overlap => "overlap / D",
            StopKind::EnergyBlowUp => "energy error %",
            StopKind::DegenerateOrientation | StopKind::QuatNormDrift => "| ||q|| - 1 |",
            StopKind::ScalarSingularity => "|omega| dt / 2",
            StopKind::Interrupted { .. } => "signal",
        }
    }

    /// Whether the guard judged a completed step (all but the scalar pole,
    /// which fires with the state half advanced, and an interrupt).
    pub fn after_step(&self) -> bool {
        !matches!(self, StopKind::ScalarSingularity)
    }

    /// The message up to its explanation, for tables (`fibresim stress`).
    pub fn short(&self) -> &'static str {
        match self {
            StopKind::NonFiniteState => "non-finite state",
            StopKind::NonFiniteEnergy => "non-finite energy",
            StopKind::Overlap => "overlap beyond the Hertz range",
            StopKind::EnergyBlowUp => "energy blow-up",
            StopKind::DegenerateOrientation => "degenerate orientation",
            StopKind::QuatNormDrift => "quaternion norm drift",
            StopKind::ScalarSingularity => "scalar-factor singularity",
            StopKind::Interrupted { .. } => "interrupted",
        }
    }
}

impl std::fmt::Display for StopKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StopKind::NonFiniteState => f.write_str(
                "non-finite state (position, velocity, orientation or spin is NaN or infinite)",
            ),
            StopKind::NonFiniteEnergy => {
                f.write_str("non-finite energy (the state has overflowed)")
            }
            StopKind::Overlap => {
                f.write_str("overlap beyond the Hertz range (impact too fast or dt too large)")
            }
            StopKind::EnergyBlowUp => {
                f.write_str("energy blow-up (full-budget energy error above the limit)")
            }
            StopKind::DegenerateOrientation => {
                f.write_str("degenerate orientation (the rotation update overflowed)")
            }
            StopKind::QuatNormDrift => f.write_str("quaternion norm drift"),
            StopKind::ScalarSingularity => {
                f.write_str("scalar-factor singularity (tan pole of Eq. 41); reduce dt or use pcdm")
            }
            StopKind::Interrupted { checkpoint, resume } => write!(
                f,
                "interrupted (SIGINT); checkpoint written to {}; resume with `{resume}`",
                checkpoint.display()
            ),
        }
    }
}

/// A named, early stop of a run that would otherwise produce garbage.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnosis {
    /// What stopped the run.
    pub kind: StopKind,
    /// The step of the stop.
    pub step: u64,
    /// Its time, s.
    pub t: f64,
    /// Global id of the body concerned, if one is.
    pub body: Option<u64>,
    /// The quantity's value.
    pub value: f64,
    /// The limit it crossed.
    pub limit: f64,
}

impl Diagnosis {
    /// The quantity that crossed its limit (see [`StopKind::quantity`]).
    pub fn quantity(&self) -> &'static str {
        self.kind.quantity()
    }
}

/// `summary.json`'s `stopped`: `{kind, step, t, body, quantity, value, limit}`.
impl serde::Serialize for Diagnosis {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("Diagnosis", 7)?;
        st.serialize_field("kind", &self.kind.to_string())?;
        st.serialize_field("step", &self.step)?;
        st.serialize_field("t", &self.t)?;
        st.serialize_field("body", &self.body)?;
        st.serialize_field("quantity", self.quantity())?;
        st.serialize_field("value", &self.value)?;
        st.serialize_field("limit", &self.limit)?;
        st.end()
    }
}

impl std::fmt::Display for Diagnosis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} at step {} (t = {} s)",
            self.kind,
            self.step,
            crate::fmt::short(self.t)
        )?;
        if let Some(b) = self.body {
            write!(f, ", body {b}")?;
        }
        let quantity = self.quantity();
        if !self.value.is_finite() {
            // A non-numeric stop has no limit to compare with: say what is not
            // finite.
            let v = if self.value.is_nan() {
                "NaN"
            } else if self.value > 0.0 {
                "+inf"
            } else {
                "-inf"
            };
            return write!(f, ": {quantity} is {v} (must be finite)");
        }
        write!(f, ": {quantity} = {}", crate::fmt::short(self.value))?;
        if self.limit.is_finite() && self.limit < f64::MAX {
            write!(f, " exceeds the limit {}", crate::fmt::short(self.limit))
        } else {
            write!(f, " is out of range")
        }
    }
}
