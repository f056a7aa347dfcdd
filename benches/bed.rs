//! Fibre beds: fibre-steps per second with 1 and 2 threads, and heap bytes
//! per fibre, as medians over repeated runs (a `--bench`-style command, not
//! criterion: one sample is hundreds of steps of a whole bed).
//!
//! ```sh
//! cargo bench --bench bed -- scenarios/bed_10k.toml             # a bed file
//! cargo bench --bench bed -- --lattice 100000                   # N fibres on a lattice
//! cargo bench --bench bed -- FILE --steps 200 --repeats 5 --threads 1,2
//! cargo bench --bench bed -- FILE --csv scaling.csv             # and append rows
//! ```
//!
//! `--csv FILE` appends one row per thread count (header when the file is
//! new), for `fibresim plot scaling.csv --x fibres --column fibre_steps_per_s`;
//! its heap column is the world's heap on that many threads (the pool's
//! blocks included) plus the scene's share as `fibresim run` holds it.
//!
//! Per run it prints: fibres, steps, median fibre-steps/s and CPU time per
//! fibre-step per thread count, the parallel efficiency and the CPU time on
//! T threads over that on one, each stage's wall time per fibre-step on
//! each thread count (one clocked run), the neighbour-list builds and candidate pairs
//! per fibre, touching contacts per fibre, the end-involved scans and
//! remembered answers, the scans' fallbacks and parry calls (per step, the
//! start's computation apart), the stage shares (one clocked
//! run), the heap in use per fibre after loading and while stepping
//! (a counting allocator wraps the system one), and the allocations of the
//! timed steps (the most of any run: a settled bed should make none).

#[path = "common/stepping.rs"]
mod stepping;
use fibresim::integrate::step::{StageTimes, World};
use fibresim::scenario::Scene;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use stepping::{median, Steps};

/// The system allocator, counting the bytes in use, their peak, and the
/// allocations (`alloc` and `realloc` calls).
struct Counting;

static IN_USE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(l) };
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        if !p.is_null() {
            let now = IN_USE.fetch_add(l.size(), Ordering::Relaxed) + l.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) };
        IN_USE.fetch_sub(l.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, l, new) };
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        if !q.is_null() {
            if new > l.size() {
                let now = IN_USE.fetch_add(new - l.size(), Ordering::Relaxed) + new - l.size();
                PEAK.fetch_max(now, Ordering::Relaxed);
            } else {
                IN_USE.fetch_sub(l.size() - new, Ordering::Relaxed);
            }
        }
        q
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// `n` fibres (D = 0.01, L = 0.03) on a lattice in a box, tilted at random,
/// at rest under gravity, each cell a little wider than a fibre: a loose
/// stack that starts touching as it falls. Built in memory (no start-up
/// overlap check is needed: the cells keep the fibres apart).
fn lattice(n: usize) -> Scene {
    let (d, l) = (0.01f64, 0.03f64);
    let cell = (d * d + l * l).sqrt() * 1.02;
    let side = ((n as f64).sqrt() / 2.0).ceil().max(1.0) as usize;
    let layers = n.div_ceil(side * side);
    let max = [side as f64 * cell, side as f64 * cell, layers as f64 * cell];
    let mut text = format!(
        "[simulation]\ndt = 1e-6\nt_end = 1e-6\n[world]\ngravity = [0.0, 0.0, -9.81]\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [{}, {}, {}]\nyoung = 5e7\npoisson = 0.35\n[[body]]\nshape = \"fibre\"\ndiameter = {d}\nlength = {l}\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [{h}, {h}, {h}]\n",
        max[0], max[1], max[2], h = 0.5 * cell
    );
    text.push('\n');
    let mut scene = fibresim::scenario::parse_str(&text, "<lattice>").expect("one-body template");
    let template = scene.bodies[0];
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    scene.bodies = fibresim::body::Bodies::uniform(template, n);
    scene.initial.clear();
    scene.names.clear();
    // Exact sizes, as the loader's (a body file's tables are moved in
    // whole): pushes would leave up to 2× capacity.
    scene.initial.reserve_exact(n);
    for k in 0..n {
        let (i, j, z) = (k % side, (k / side) % side, k / (side * side));
        let c = |g: usize| (g as f64 + 0.5) * cell;
        let axis = glam::DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
        let q = glam::DQuat::from_rotation_arc(glam::DVec3::X, axis);
        // No name, as for the bodies of a body file (`Scene::name` gives
        // `body<id>`): a String per body is not what a bed costs.
        scene.initial.push(fibresim::body::BodyState {
            x: glam::DVec3::new(c(i), c(j), c(z)),
            v: glam::DVec3::ZERO,
            rot: fibresim::body::RotState {
                q,
                omega_b: glam::DVec3::ZERO,
            },
        });
    }
    scene.ids = fibresim::scenario::Ids::Sequential(n);
    scene
}

fn main() {
    let args = stepping::args();
    let flag = |name: &str| stepping::flag(&args, name);
    let steps: u64 = flag("--steps").map_or(200, |s| s.parse().expect("--steps N"));
    let repeats: usize = flag("--repeats").map_or(5, |s| s.parse().expect("--repeats N"));
    let threads: Vec<usize> = flag("--threads")
        .unwrap_or_else(|| "1,2".into())
        .split(',')
        .map(|s| s.parse().expect("--threads 1,2"))
        .collect();
    let before = IN_USE.load(Ordering::Relaxed);
    let t0 = Instant::now();
    let mut scene = match flag("--lattice") {
        Some(n) => lattice(n.parse().expect("--lattice N")),
        None => {
            let path = args
                .iter()
                .find(|a| !a.starts_with("--") && flag_value(&args, a))
                .expect("give a scenario file or --lattice N");
            fibresim::scenario::load(std::path::Path::new(path)).expect("the bed loads")
        }
    };
    let load_s = t0.elapsed().as_secs_f64();
    let n = scene.bodies.len();
    let loaded = IN_USE.load(Ordering::Relaxed) - before;
    println!(
        "{} fibres loaded in {load_s:.2} s; heap after loading {:.0} B/fibre (peak {:.0} B/fibre)",
        n,
        loaded as f64 / n as f64,
        (PEAK.load(Ordering::Relaxed) - before) as f64 / n as f64
    );

    let (mut rates, mut cpus, mut worlds) = (vec![], vec![], vec![]);
    for &t in &threads {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap();
        let (samples, cpu, world, allocs): (Vec<f64>, Vec<f64>, usize, usize) =
            pool.install(|| {
                let (mut samples, mut cpu, mut world, mut allocs) = (vec![], vec![], 0, 0);
                for _ in 0..repeats {
                    let base = IN_USE.load(Ordering::Relaxed);
                    let mut w = World::new(&scene);
                    scene.sim.rotator().visit(Steps(&mut w, 2)); // warm the buffers
                    let (start, cpu0) = (Instant::now(), cpu_seconds());
                    let allocs0 = ALLOCS.load(Ordering::Relaxed);
                    scene.sim.rotator().visit(Steps(&mut w, steps));
                    allocs = allocs.max(ALLOCS.load(Ordering::Relaxed) - allocs0);
                    let fibre_steps = (steps * n as u64) as f64;
                    samples.push(fibre_steps / start.elapsed().as_secs_f64());
                    cpu.push(1e9 * (cpu_seconds() - cpu0) / fibre_steps);
                    // The world's heap on t threads (the pool's blocks included).
                    world = world.max(IN_USE.load(Ordering::Relaxed) - base);
                }
                // One clocked run: each stage's wall time per fibre-step on
                // t threads (where a second thread gains or loses).
                let mut w = World::new(&scene);
                scene.sim.rotator().visit(Steps(&mut w, 2));
                w.timers = Some(StageTimes::default());
                scene.sim.rotator().visit(Steps(&mut w, steps));
                let clocked = w.timers.unwrap();
                let per = |d: std::time::Duration| 1e9 * d.as_secs_f64() / (steps * n as u64) as f64;
                println!(
                    "threads {t}, clocked: forces {:.0} ns, integration {:.0} ns, guards {:.0} ns per fibre-step",
                    per(clocked.forces),
                    per(clocked.integrate),
                    per(clocked.guards)
                );
                (samples, cpu, world, allocs)
            });
        let (m, c) = (median(samples), median(cpu));
        rates.push((t, m));
        cpus.push((t, c));
        worlds.push((t, world));
        println!(
            "threads {t}: median {:.3} M fibre-steps/s, {c:.0} ns of CPU per fibre-step ({repeats} runs of {steps} steps); world heap {:.0} B/fibre; {allocs} allocations in {steps} steps (the most of any run)",
            m / 1e6,
            world as f64 / n as f64
        );
    }
    if let (Some(&(1, one)), Some(&(t, many))) = (rates.first(), rates.last()) {
        if t > 1 {
            println!(
                "parallel efficiency on {t} threads: {:.0} %; CPU per fibre-step {:.0} % of one thread's",
                100.0 * many / (one * t as f64),
                100.0 * cpus.last().unwrap().1 / cpus[0].1
            );
        }
    }

    // One clocked run on one thread: stage shares, lists, contacts, memory.
    // As `fibresim run`, the world takes the scene's step-0 states (moved:
    // their bytes leave the scene's share for the world's).
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let initial = std::mem::take(&mut scene.initial);
    let moved = initial.capacity() * std::mem::size_of::<fibresim::body::BodyState>();
    let scene = &scene;
    let (touching, builds) = pool.install(|| {
        let mut w = World::from_states(scene, initial);
        // The start's computation scans every pair (no memory yet): apart.
        let start = w.contacts.as_ref().map(|c| c.kernel_counters()).unwrap_or_default();
        w.timers = Some(StageTimes::default());
        scene.sim.rotator().visit(Steps(&mut w, steps));
        let in_use = IN_USE.load(Ordering::Relaxed) - before;
        let heap = in_use - (loaded - moved);
        let t = w.timers.unwrap();
        let total = (t.integrate + t.forces + t.guards).as_secs_f64();
        let share = |d: std::time::Duration| 100.0 * d.as_secs_f64() / total;
        let c = w.contacts.as_ref().expect("a bed has contacts");
        println!(
            "one thread, clocked: forces {:.0} %, integration {:.0} %, guards {:.0} %; {} list builds in {steps} steps; {:.2} touching contacts per fibre",
            share(t.forces),
            share(t.integrate),
            share(t.guards),
            c.neighbour_builds(),
            c.stats.touching as f64 / n as f64
        );
        // The steps' (the start's computation apart).
        let k = c.kernel_counters();
        let per = |now: u64, then: u64| (now - then) as f64 / steps as f64;
        println!(
            "kernels: {:.2} pairs passed over (apart in every regime), {:.2} end-involved feature scans and {:.2} remembered answers per fibre per step, {:.1} scans a step fell back to the iterative search, {:.1} parry calls a step",
            per(k.passed_over, start.passed_over) / n as f64,
            per(k.end_scans, start.end_scans) / n as f64,
            per(k.remembered, start.remembered) / n as f64,
            per(k.fallbacks, start.fallbacks),
            per(k.parry_calls, start.parry_calls)
        );
        println!(
            "heap while stepping: {:.0} B/fibre for the world (states, forces, contact stage), {:.0} B/fibre with the scene ({:.0} B/fibre)",
            heap as f64 / n as f64,
            in_use as f64 / n as f64,
            (in_use - heap) as f64 / n as f64
        );
        (c.stats.touching as f64 / n as f64, c.neighbour_builds())
    });
    // Per thread count, the world's heap on that many threads plus the
    // scene's share once its step-0 states are moved out (as `run` holds it).
    let scene_share = (loaded - moved) as f64 / n as f64;
    let heaps: Vec<f64> = worlds
        .iter()
        .map(|&(t, w)| {
            let h = w as f64 / n as f64 + scene_share;
            println!("heap while stepping on {t} thread(s): {h:.0} B/fibre with the scene");
            h
        })
        .collect();
    if let Some(path) = flag("--csv") {
        append_csv(&path, n, steps, &rates, touching, builds, &heaps);
    }
}

/// Append the medians to `path`, one row per thread count.
fn append_csv(
    path: &str,
    n: usize,
    steps: u64,
    rates: &[(usize, f64)],
    touching: f64,
    builds: u64,
    heaps: &[f64],
) {
    use std::io::Write;
    let new = !std::path::Path::new(path).exists();
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .unwrap_or_else(|e| panic!("cannot open {path}: {e}"));
    if new {
        writeln!(f, "fibres,threads,fibre_steps_per_s,ns_per_fibre_step,parallel_efficiency,steps,list_builds,touching_per_fibre,heap_bytes_per_fibre").unwrap();
    }
    let one = rates.iter().find(|r| r.0 == 1).map(|r| r.1);
    for (&(t, rate), heap) in rates.iter().zip(heaps) {
        let eff = one.map_or(f64::NAN, |o| rate / (o * t as f64));
        writeln!(
            f,
            "{n},{t},{rate:.0},{:.2},{eff:.3},{steps},{builds},{touching:.3},{heap:.0}",
            1e9 / rate
        )
        .unwrap();
    }
}

/// CPU time of the whole process (every thread), s: `utime + stime` of
/// `/proc/self/stat`, in the kernel's fixed 100 ticks per second. On a
/// loaded machine the wall time measures the load; the CPU time of the same
/// steps on 1 and on T threads says how much work the pool adds (its
/// spinning included), whoever else runs.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name, which is in parentheses: utime and
    // stime are the 12th and 13th.
    let rest = stat.rsplit(')').next().unwrap_or("");
    let ticks: f64 = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|f| f.parse::<f64>().ok())
        .sum();
    ticks / 100.0
}

/// Whether `a` is not the value of a `--flag`.
fn flag_value(args: &[String], a: &str) -> bool {
    let i = args.iter().position(|x| x == a).unwrap_or(0);
    i == 0 || !args[i - 1].starts_with("--")
}
