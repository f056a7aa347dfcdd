use fibresim::contact::*;
use fibresim::integrate::rotate::Pcdm;
use fibresim::output::Checkpoint;
use glam::{DQuat, DVec3};
fn energy_force(a: &FibreGeom, b: &FibreGeom, law: &HertzLaw) -> (f64, DVec3, DVec3, Vec<ContactPoint>) {
    let mut pts = vec![];
    contact_fibre_fibre(a, b, &mut pts);
    let mut u = 0.0; let mut f = DVec3::ZERO; let mut t = DVec3::ZERO;
    for p in &pts { u += p.weight * law.energy(p.overlap); let fi = p.weight * law.force(p.overlap) * p.normal; f += fi; t += (p.point - a.centre).cross(fi); }
    (u, f, t, pts)
}
fn main() {
    let c = Checkpoint::read(std::path::Path::new("/tmp/dbg/checkpoint.json")).unwrap();
    let scene = fibresim::run::scene_from_checkpoint(&c, Some(0.2747)).unwrap();
    let mut w = fibresim::integrate::step::World::new(&scene);
    let states = c.states.iter().map(|s| fibresim::output::checkpoint::state_from_bits(s).unwrap()).collect();
    w.restore(states, c.step);
    while w.step < scene.sim.steps { w.step::<Pcdm>().unwrap(); }
    let g = |i: usize| FibreGeom { centre: w.states[i].x, axis: w.states[i].rot.q * DVec3::X, radius: 0.005, half_length: 0.0125 };
    let (a, b) = (g(0), g(3));
    println!("A {:?}\nB {:?}", a, b);
    let law = HertzLaw::fibre_fibre(0.01, 5e7, 0.35, 0.01, 5e7, 0.35);
    let (u0, f, t, pts) = energy_force(&a, &b, &law);
    println!("U {u0:e} F {f} T {t} pts {:?}", pts);
    let eps = 1e-9;
    for k in 0..3 {
        let mut a2 = a; a2.centre[k] += eps;
        let mut a1 = a; a1.centre[k] -= eps;
        let du = (energy_force(&a2, &b, &law).0 - energy_force(&a1, &b, &law).0) / (2.0*eps);
        println!("trans {k}: -dU/dx {:e}  F {:e}", -du, f[k]);
    }
    for k in 0..3 {
        let mut e = DVec3::ZERO; e[k] = 1.0;
        let rot = |s: f64| { let mut a2 = a; let q = DQuat::from_axis_angle(e, s); a2.axis = q * a.axis; a2 };
        let du = (energy_force(&rot(eps), &b, &law).0 - energy_force(&rot(-eps), &b, &law).0) / (2.0*eps);
        println!("rot {k}: -dU/dth {:e}  T {:e}", -du, t[k]);
    }
}
