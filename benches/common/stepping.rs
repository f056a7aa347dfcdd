//! What the median-printing bed benches share: stepping a world with the
//! scene's rotator, the median, and `--name value` flags.

use fibresim::integrate::rotate::{Rotator, RotatorVisitor};
use fibresim::integrate::step::World;

/// Run `steps` steps of the world with rotator `R`.
pub struct Steps<'a, 's>(pub &'a mut World<'s>, pub u64);

impl RotatorVisitor for Steps<'_, '_> {
    type Output = ();
    fn visit<R: Rotator>(self) {
        for _ in 0..self.1 {
            self.0.step::<R>().expect("the bed stays stable");
        }
    }
}

pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The bench's arguments (cargo's `--bench` left out).
pub fn args() -> Vec<String> {
    std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect()
}

/// The value after `--name` in `args`, if given.
pub fn flag(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .cloned()
}
