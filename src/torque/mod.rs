//! Prescribed world-frame torques as functions of time (test cases 3 and 4).
//!
//! Each component is a constant or an expression in `t` (seconds) compiled once
//! ([`Expr`], flattened into a [`Program`]), e.g. `"5e-4*sin(200*pi*t)"`, `"1e-5*exp(3+24*t)"`, `"1e-5*5^(52*t)"`.
//! Cost per evaluation is measured in `benches/rotators.rs` (docs/performance.md).
//! A manufactured solution's torque ([`crate::reference::Manufactured`]) is
//! the other source: computed from its closed form, never written by hand.

mod expr;

pub use expr::{Expr, Program};
use glam::DVec3;

/// One compiled component; a constant is kept apart so `0` costs nothing.
#[derive(Debug, Clone)]
enum Component {
    Const(f64),
    Program(Program),
}

impl Component {
    fn parse(text: &str) -> Result<Self, String> {
        let c = match Expr::parse(text).map_err(|e| format!("cannot compile `{text}`: {e}"))? {
            Expr::Const(c) => Component::Const(c),
            e => Component::Program(
                Program::compile(&e).map_err(|e| format!("cannot compile `{text}`: {e}"))?,
            ),
        };
        // Reject expressions that are not finite at t = 0 right away (e.g. `1/t`).
        let v0 = c.eval(0.0);
        if !v0.is_finite() {
            return Err(format!("`{text}` is not finite at t = 0 (value {v0})"));
        }
        Ok(c)
    }

    #[inline]
    fn eval(&self, t: f64) -> f64 {
        match self {
            Component::Const(c) => *c,
            Component::Program(p) => p.eval(t),
        }
    }
}

/// A world-frame torque `τ(t)`: given component-wise, or the torque of a
/// manufactured solution.
#[derive(Debug, Clone)]
pub struct PrescribedTorque {
    source: Source,
}

#[derive(Debug, Clone)]
enum Source {
    Components([Component; 3]),
    Manufactured(std::sync::Arc<crate::reference::Manufactured>),
}

impl PrescribedTorque {
    /// Compile the three components; the error names the failing component.
    pub fn parse(components: &[String; 3]) -> Result<Self, (usize, String)> {
        let c0 = Component::parse(&components[0]).map_err(|e| (0, e))?;
        let c1 = Component::parse(&components[1]).map_err(|e| (1, e))?;
        let c2 = Component::parse(&components[2]).map_err(|e| (2, e))?;
        Ok(PrescribedTorque {
            source: Source::Components([c0, c1, c2]),
        })
    }

    /// The torque that drives manufactured solution `m`.
    pub fn manufactured(m: std::sync::Arc<crate::reference::Manufactured>) -> Self {
        PrescribedTorque {
            source: Source::Manufactured(m),
        }
    }

    /// Whether every component is the constant 0: a torque that does no
    /// work (the time-step advice then bounds its body's energy as any other).
    pub fn is_zero(&self) -> bool {
        match &self.source {
            Source::Components(c) => c
                .iter()
                .all(|c| matches!(c, Component::Const(v) if *v == 0.0)),
            Source::Manufactured(_) => false,
        }
    }

    /// World torque at time `t`.
    #[inline]
    pub fn at(&self, t: f64) -> DVec3 {
        match &self.source {
            Source::Components(c) => DVec3::new(c[0].eval(t), c[1].eval(t), c[2].eval(t)),
            Source::Manufactured(m) => m.torque(t),
        }
    }
}
