//! Debug: replay from a checkpoint and check every live contact's force and
//! torque against finite differences of its potential.
use fibresim::contact::*;
use fibresim::integrate::rotate::Leapfrog;
use fibresim::output::Checkpoint;
use glam::{DQuat, DVec3};
fn pair(a: &FibreGeom, b: &FibreGeom, law: &HertzLaw, wall: Option<&Wall>) -> (f64, DVec3, DVec3, Vec<ContactPoint>) {
    let mut pts = vec![];
    match wall { Some(w) => contact_fibre_wall(a, w, &mut pts), None => contact_fibre_fibre(a, b, &mut pts) }
    let mut u = 0.0; let mut f = DVec3::ZERO; let mut t = DVec3::ZERO;
    for p in &pts { u += p.weight * law.energy(p.overlap); let fi = p.weight * law.force(p.overlap) * p.normal; f += fi; t += (p.point - a.centre).cross(fi); }
    (u, f, t, pts)
}
fn check(a: &FibreGeom, b: &FibreGeom, law: &HertzLaw, wall: Option<&Wall>) -> Option<String> {
    let (u, f, t, pts) = pair(a, b, law, wall);
    if pts.is_empty() { return None; }
    let eps = 1e-8;
    let mut worst: f64 = 0.0;
    let mut msg = String::new();
    for k in 0..3 {
        let mut a2 = *a; a2.centre[k] += eps; let mut a1 = *a; a1.centre[k] -= eps;
        let g = -(pair(&a2, b, law, wall).0 - pair(&a1, b, law, wall).0) / (2.0 * eps);
        let e = (g - f[k]).abs() / f.length().max(1e-12);
        if e > worst { worst = e; msg = format!("F{k}: fd {g:e} vs {:e}", f[k]); }
        let rot = |s: f64| { let mut a2 = *a; a2.axis = DQuat::from_axis_angle(DVec3::AXES[k], s) * a.axis; a2 };
        let g = -(pair(&rot(eps), b, law, wall).0 - pair(&rot(-eps), b, law, wall).0) / (2.0 * eps);
        let scale = t.length().max(f.length() * a.radius);
        let e = (g - t[k]).abs() / scale;
        if e > worst { worst = e; msg = format!("T{k}: fd {g:e} vs {:e}", t[k]); }
    }
    Some(format!("U {u:.3e} n {} worst {worst:.1e} {msg} pts {:?}", pts.len(), pts.iter().map(|p| (p.overlap, p.normal)).collect::<Vec<_>>()))
}
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let until: f64 = std::env::args().nth(2).unwrap().parse().unwrap();
    let c = Checkpoint::read(std::path::Path::new(&path)).unwrap();
    let scene = fibresim::run::scene_from_checkpoint(&c, Some(until)).unwrap();
    let mut w = fibresim::integrate::step::World::new(&scene);
    let states = c.states.iter().map(|s| fibresim::output::checkpoint::state_from_bits(s).unwrap()).collect();
    w.restore(states, c.step);
    let e0 = w.e0_full;
    let ff = HertzLaw::fibre_fibre(0.01, 5e7, 0.35, 0.01, 5e7, 0.35);
    let fw = HertzLaw::fibre_wall(0.01, 5e7, 0.35, 5e7, 0.23);
    let walls = fibresim::contact::stage::box_walls(scene.walls.as_ref().unwrap());
    while w.step < scene.sim.steps {
        w.step::<Leapfrog>().unwrap();
        if w.step % 200 != 0 { continue; }
        let g: Vec<FibreGeom> = w.states.iter().map(|s| FibreGeom { centre: s.x, axis: s.rot.q * DVec3::X, radius: 0.005, half_length: 0.0125 }).collect();
        let mut line = format!("{} err {:.4e}", w.step, (w.ledger.total_full() - e0) / e0 * 100.0);
        for i in 0..9 {
            for j in i + 1..9 { if let Some(m) = check(&g[i], &g[j], &ff, None) { line += &format!("\n   {i}-{j} sin {:.4} {m}", g[i].axis.cross(g[j].axis).length()); } }
            for (k, wl) in walls.iter().enumerate() { if let Some(m) = check(&g[i], &g[i], &fw, Some(wl)) { line += &format!("\n   {i}-wall{k} {m}"); } }
        }
        println!("{line}");
    }
}
