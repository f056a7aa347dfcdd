use fibresim::contact::*;
use fibresim::integrate::rotate::Pcdm;
use fibresim::output::Checkpoint;
use glam::DVec3;
fn main() {
    let c = Checkpoint::read(std::path::Path::new("/tmp/dbg/checkpoint.json")).unwrap();
    let scene = fibresim::run::scene_from_checkpoint(&c, Some(0.2750)).unwrap();
    let mut w = fibresim::integrate::step::World::new(&scene);
    let states = c.states.iter().map(|s| fibresim::output::checkpoint::state_from_bits(s).unwrap()).collect();
    w.restore(states, c.step);
    let e0 = w.e0_full;
    let mut pts = vec![];
    while w.step < scene.sim.steps {
        w.step::<Pcdm>().unwrap();
        if w.step % 100 == 0 {
            let geoms: Vec<FibreGeom> = w.states.iter().map(|s| FibreGeom { centre: s.x, axis: s.rot.q * DVec3::X, radius: 0.005, half_length: 0.0125 }).collect();
            let mut line = format!("{} err {:.4e} ", w.step, (w.ledger.total_full() - e0) / e0 * 100.0);
            for i in 0..9 { for j in i+1..9 {
                pts.clear();
                contact_fibre_fibre(&geoms[i], &geoms[j], &mut pts);
                if !pts.is_empty() {
                    line += &format!("[{i}-{j}: n={} {:?} d={:.3e} c={:.4} ] ", pts.len(), pts.iter().map(|p| format!("{:.3e}", p.overlap)).collect::<Vec<_>>(), (geoms[i].centre-geoms[j].centre).length(), geoms[i].axis.dot(geoms[j].axis));
                }
            }}
            for i in 0..9 { for (k, wall) in fibresim::contact::stage::box_walls(scene.walls.as_ref().unwrap()).iter().enumerate() {
                pts.clear();
                contact_fibre_wall(&geoms[i], wall, &mut pts);
                if !pts.is_empty() { line += &format!("[{i}-wall{k}: n={}] ", pts.len()); }
            }}
            println!("{line}");
        }
    }
}
