//! Fincham's leap-frog with the half-step momentum converted by the
//! predicted half-step orientation, as Fincham's paper describes (the scheme
//! is in `fincham.rs`): second order, where Yade's `q_n` makes it first.

/// Fincham's leap-frog, half-step momentum in the predicted half-step frame.
pub type FinchamMid = super::fincham::FinchamScheme<true>;
