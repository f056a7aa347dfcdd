//! The fibre–fibre kernel on one pose of `benches/kernels.rs`, many times:
//! a deterministic workload for instruction counts (the machine is shared,
//! wall clocks are not). Usage:
//!
//! ```sh
//! cargo build --release --example kernel_profile
//! valgrind --tool=callgrind --callgrind-out-file=/tmp/cg target/release/examples/kernel_profile end/rim_on_side 10000
//! ```
//!
//! prints the pose's contacts and counters; the instructions per call are
//! callgrind's total over the count (the set-up is ~1e5 instructions).
//! Without arguments it lists the poses.
//!
//! On a bed (the pairs of a real packing, not placed poses):
//!
//! ```sh
//! kernel_profile --bed scenarios/bed_10k.toml 20      # 20 steps: kernel counters
//! kernel_profile --pairs scenarios/bed_10k.toml OUT   # its end-involved pairs at t = 0, to OUT
//! kernel_profile --eval OUT [REPEATS] [CONTACTS]      # the kernel on them (and its contacts to CONTACTS)
//! ```
//!
//! `kernel_profile --remembered POSE N` times the pose as a pair that
//! remembers its scan (`contact/fibre_fibre/coherence.rs`): one scan, then
//! N calls that run the winner's kernel.

#[path = "../benches/common/poses.rs"]
mod poses;

use fibresim::contact::{
    contact_fibre_fibre, contact_fibre_fibre_remembering, ContactPoint, FibreGeom, KernelCounters,
    PairMemory,
};
use fibresim::integrate::rotate::{Rotator, RotatorVisitor};
use fibresim::integrate::step::World;
use glam::DVec3;
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::Path;

struct Steps<'a, 's>(&'a mut World<'s>, u64);

impl RotatorVisitor for Steps<'_, '_> {
    type Output = ();
    fn visit<R: Rotator>(self) {
        for _ in 0..self.1 {
            self.0.step::<R>().expect("the bed stays stable");
        }
    }
}

/// The fibres of `scene` at t = 0 as the kernels see them.
fn geoms(scene: &fibresim::scenario::Scene) -> Vec<FibreGeom> {
    scene
        .bodies
        .iter()
        .zip(&scene.initial)
        .map(|(b, s)| fibresim::contact::stage::geom(b, s))
        .collect()
}

fn parse_pairs(text: &str) -> Vec<(FibreGeom, FibreGeom)> {
    let f = |v: &[f64]| FibreGeom {
        centre: DVec3::new(v[0], v[1], v[2]),
        axis: DVec3::new(v[3], v[4], v[5]),
        radius: v[6],
        half_length: v[7],
    };
    text.lines()
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(|x| x.parse().expect("a number")).collect();
            (f(&v[..8]), f(&v[8..]))
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    match args.get(1).map(String::as_str) {
        Some("--bed") => {
            let scene = fibresim::scenario::load(Path::new(&args[2])).expect("a scene");
            let steps: u64 = args[3].parse().expect("a step count");
            let mut w = World::new(&scene);
            scene.sim.rotator().visit(Steps(&mut w, steps));
            let k = w
                .contacts
                .as_ref()
                .map(|c| c.kernel_counters())
                .unwrap_or_default();
            println!("{steps} steps: {k:?}");
            return;
        }
        Some("--pairs") => {
            let scene = fibresim::scenario::load(Path::new(&args[2])).expect("a scene");
            let g = geoms(&scene);
            let reach = g
                .iter()
                .map(|f| 2.0 * (f.half_length + f.radius))
                .fold(0.0, f64::max);
            // Cells of side `reach`: every pair within reach is in
            // neighbouring cells.
            let key = |c: DVec3| (c / reach).floor().as_ivec3();
            let mut cells: std::collections::HashMap<glam::IVec3, Vec<usize>> = Default::default();
            for (i, f) in g.iter().enumerate() {
                cells.entry(key(f.centre)).or_default().push(i);
            }
            let mut text = String::new();
            let (mut n, mut out) = (0, vec![]);
            for (i, a) in g.iter().enumerate() {
                let k = key(a.centre);
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            let Some(list) = cells.get(&(k + glam::IVec3::new(dx, dy, dz))) else {
                                continue;
                            };
                            for &j in list {
                                if j <= i {
                                    continue;
                                }
                                let b = &g[j];
                                let mut c = KernelCounters::default();
                                out.clear();
                                contact_fibre_fibre(a, b, &mut out, &mut c);
                                if c.end_scans > 0 {
                                    n += 1;
                                    for f in [a, b] {
                                        let (p, u) = (f.centre, f.axis);
                                        write!(
                                            text,
                                            "{:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} ",
                                            p.x, p.y, p.z, u.x, u.y, u.z, f.radius, f.half_length
                                        )
                                        .unwrap();
                                    }
                                    text.pop();
                                    text.push('\n');
                                }
                            }
                        }
                    }
                }
            }
            std::fs::write(&args[3], text).expect("written");
            println!("{n} end-involved pairs");
            return;
        }
        Some("--eval") => {
            let pairs = parse_pairs(&std::fs::read_to_string(&args[2]).expect("pairs"));
            let repeats: u64 = args.get(3).map_or(1, |c| c.parse().expect("a count"));
            let (mut out, mut k) = (
                Vec::<ContactPoint>::with_capacity(8),
                KernelCounters::default(),
            );
            let mut text = String::new();
            for r in 0..repeats {
                for (a, b) in &pairs {
                    out.clear();
                    contact_fibre_fibre(black_box(a), black_box(b), &mut out, &mut k);
                    if r == 0 && args.get(4).is_some() {
                        for c in &out {
                            writeln!(
                                text,
                                "{:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e}",
                                c.overlap,
                                c.weight,
                                c.normal.x,
                                c.normal.y,
                                c.normal.z,
                                c.point.x,
                                c.point.y,
                                c.point.z
                            )
                            .unwrap();
                        }
                        text.push_str("--\n");
                    }
                }
            }
            if let Some(p) = args.get(4) {
                std::fs::write(p, text).expect("written");
            }
            println!("{} pairs x {repeats}: {k:?}", pairs.len());
            return;
        }
        _ => {}
    }
    let poses = poses::poses();
    let Some(name) = args.get(1) else {
        for (name, _, _) in &poses {
            println!("{name}");
        }
        return;
    };
    let remembered = name == "--remembered";
    let name = if remembered { &args[2] } else { name };
    let count: u64 = args
        .get(if remembered { 3 } else { 2 })
        .map_or(10_000, |c| c.parse().expect("a count"));
    let Some((_, a, b)) = poses.iter().find(|p| p.0 == name) else {
        eprintln!("no pose {name}; run without arguments for the list");
        std::process::exit(2);
    };
    let (mut out, mut k) = (Vec::with_capacity(8), KernelCounters::default());
    let mut memory = PairMemory::default();
    for _ in 0..count {
        out.clear();
        if remembered {
            let m = Some((&mut memory, 0.0));
            contact_fibre_fibre_remembering(black_box(a), black_box(b), &mut out, &mut k, m);
        } else {
            contact_fibre_fibre(black_box(a), black_box(b), &mut out, &mut k);
        }
        black_box(out.len());
    }
    println!(
        "{name}: {} contact point(s) per call, counters over {count} calls: {k:?}",
        out.len()
    );
}
