//! The cost of a frame, at 10⁴ and 10⁵ fibres: a VTK frame written by the
//! run's observer (recount of contacts, gather, zlib, file), `fibresim
//! render` of that frame to PNG (read, draw, encode), one GIF frame (draw,
//! quantise, encode), and one step of the run for scale. The scenes are
//! lattices of non-touching fibres of test case 1's size in a box, with
//! pseudo-random orientations and motions (incompressible-looking data: the
//! bytes per fibre are an upper estimate). Prints the bytes per fibre.
//! Then a checkpoint's write at 10⁵ and 10⁶ fibres (group `checkpoint`).
//! Run: `cargo bench --bench frames` (about 4 min), or `-- checkpoint`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use fibresim::integrate::rotate::Pcdm;
use fibresim::integrate::step::World;
use fibresim::output::VtkSeries;
use fibresim::render::{draw_frame, write_png, RenderOptions, Source};
use fibresim::run::stats::RunStats;
use fibresim::run::{Observer, View};
use fibresim::scenario::{parse_str, Scene};
use glam::{DQuat, DVec3};
use std::time::Duration;

/// `n` fibres on a cubic lattice of pitch 0.04 m (a fibre's bounding
/// sphere has radius 0.0135 m: none touch), random axes, v and ω.
fn lattice(n: usize) -> Scene {
    let side = (n as f64).cbrt().ceil() as usize;
    let edge = 0.04 * side as f64;
    let text = format!(
        "[simulation]\ndt = 1e-7\nt_end = 1e-5\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [{edge}, {edge}, {edge}]\nyoung = 5e7\npoisson = 0.23\n\
         [[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.025\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [0.02, 0.02, 0.02]\n"
    );
    let mut scene = parse_str(&text, "<lattice>").unwrap();
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let (body, state) = (scene.bodies[0], scene.initial[0]);
    scene.bodies = fibresim::body::Bodies::uniform(body, n);
    scene.names = (0..n).map(|i| format!("f{i}")).collect();
    scene.ids = fibresim::scenario::Ids::Sequential(n);
    scene.initial = (0..n)
        .map(|k| {
            let (i, j, l) = (k % side, (k / side) % side, k / (side * side));
            let c = |g: usize| 0.02 + 0.04 * g as f64;
            let mut s = state;
            s.x = DVec3::new(c(i), c(j), c(l));
            s.rot.q = DQuat::from_xyzw(rnd(), rnd(), rnd(), rnd()).normalize();
            s.v = DVec3::new(rnd(), rnd(), rnd());
            s.rot.omega_b = 50.0 * DVec3::new(rnd(), rnd(), rnd());
            s
        })
        .collect();
    scene
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("frames");
    g.sample_size(10).measurement_time(Duration::from_secs(4));
    for n in [10_000usize, 100_000] {
        let scene = lattice(n);
        let mut world = World::new(&scene);
        let dir = tempfile::tempdir().unwrap();
        let stats = RunStats::new(&world.ledger);
        let mut vtk = VtkSeries::new(dir.path(), 1);
        {
            let v = View {
                world: &world,
                stats: &stats,
            };
            vtk.start(&v).unwrap();
            vtk.row(&v).unwrap();
        }
        let frame = dir.path().join("vtk/fibres_0.vtp");
        let bytes = std::fs::metadata(&frame).unwrap().len();
        println!(
            "{n} fibres: a VTK frame is {bytes} bytes, {:.1} bytes per fibre",
            bytes as f64 / n as f64
        );
        g.bench_with_input(BenchmarkId::new("vtk_frame", n), &n, |b, _| {
            let v = View {
                world: &world,
                stats: &stats,
            };
            b.iter(|| vtk.row(&v).unwrap())
        });
        let png = dir.path().join("still.png");
        let opts = RenderOptions::default();
        g.bench_with_input(BenchmarkId::new("render_vtp_to_png", n), &n, |b, _| {
            b.iter(|| {
                let s = Source::open(&frame, None).unwrap();
                let f = s.frame(0).unwrap();
                write_png(&draw_frame(&f, &opts), &png).unwrap()
            })
        });
        let f = Source::open(&frame, None).unwrap().frame(0).unwrap();
        g.bench_with_input(BenchmarkId::new("draw", n), &n, |b, _| {
            b.iter(|| draw_frame(&f, &opts))
        });
        g.bench_with_input(BenchmarkId::new("gif_frame", n), &n, |b, _| {
            let pm = draw_frame(&f, &opts);
            let rgb: Vec<u8> = pm
                .data()
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect();
            b.iter(|| {
                let gf = gif::Frame::from_rgb_speed(1000, 800, &rgb, 10);
                let mut out = Vec::new();
                let mut e = gif::Encoder::new(&mut out, 1000, 800, &[]).unwrap();
                e.write_frame(&gf).unwrap();
                drop(e);
                out.len()
            })
        });
        g.bench_with_input(BenchmarkId::new("step", n), &n, |b, _| {
            b.iter(|| world.step::<Pcdm>().unwrap())
        });
    }
    g.finish();
}

/// A checkpoint of 10⁵ and 10⁶ fibres (the target: ≤ 5 s to write at
/// 10⁶): the driver's copy of the states, the states file (encoded, hashed,
/// written, renamed) and the JSON.
fn checkpoint(c: &mut Criterion) {
    use fibresim::output::Checkpoint;
    let mut g = c.benchmark_group("checkpoint");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    for n in [100_000usize, 1_000_000] {
        let scene = lattice(n);
        let world = World::new(&scene);
        let stats = RunStats::new(&world.ledger);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("checkpoint.json");
        Checkpoint::of::<Pcdm>(&world, &stats).write(&path).unwrap();
        let bytes = std::fs::metadata(path.with_extension("states"))
            .unwrap()
            .len()
            + std::fs::metadata(&path).unwrap().len();
        println!(
            "{n} fibres: a checkpoint is {bytes} bytes, {:.1} bytes per fibre",
            bytes as f64 / n as f64
        );
        g.bench_with_input(BenchmarkId::new("write", n), &n, |b, _| {
            b.iter(|| Checkpoint::of::<Pcdm>(&world, &stats).write(&path).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench, checkpoint);
criterion_main!(benches);
