//! PCDM with the mid-step torque taken at `t_n` instead of `t_n + δt/2`
//! (the scheme is in `pcdm.rs`): the other reading of Eq. 57–62, which do not
//! say at which time the torque of step 3 is taken. First order for
//! time-dependent torques; the same scheme as `pcdm` for contact torques.

/// PCDM with the mid-step torque at `t_n`.
pub type PcdmStart = super::pcdm::PcdmScheme<false>;
