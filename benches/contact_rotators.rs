//! The cost of each rotator on a contact scene: nanoseconds per body-step of
//! the whole `World::step` (forces, contacts, the rotator), as medians over
//! alternated rounds (every rotator once per round, so a load that comes and
//! goes on a shared machine falls on all of them alike). A `--bench`-style
//! command, not criterion: one sample is hundreds of steps of a whole scene.
//!
//! ```sh
//! cargo bench --bench contact_rotators -- SCENE.toml       # every contact rotator
//! cargo bench --bench contact_rotators -- SCENE.toml --rotators pcdm,leapfrog,nosquish \
//!     --dt 4e-6 --steps 2000 --rounds 7 --threads 1
//! ```
//!
//! Prints the load average before and after, then per rotator the median
//! CPU time per body-step (this thread's time on a core, which the other
//! processes of a shared machine do not inflate as they do the wall time),
//! its spread (min–max) over the rounds, its ratio to the fastest, and the
//! median wall time. The steps start from the scene's initial state each
//! round, so every rotator times the same stretch of the motion.

use fibresim::integrate::rotate::{Rotator, RotatorKind, RotatorVisitor};
use fibresim::integrate::step::World;
use fibresim::scenario::{self, Scene, SimParams};
use std::hint::black_box;
use std::time::Instant;

/// `n` steps with the rotator the visitor is called with (one dispatch),
/// up to a guard's stop.
struct Steps<'a, 's>(&'a mut World<'s>, u64);

impl RotatorVisitor for Steps<'_, '_> {
    type Output = ();
    fn visit<R: Rotator>(self) {
        for _ in 0..self.1 {
            if black_box(self.0.step::<R>()).is_err() {
                return;
            }
        }
    }
}

/// The CPU time this thread has run, s (Linux: `/proc/thread-self/schedstat`;
/// NaN elsewhere). Unlike the wall time it does not count the time other
/// processes hold the cores, so it is the cost to quote on a shared machine.
fn thread_cpu_s() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |ns| ns * 1e-9)
}

/// Wall and CPU seconds per body-step of up to `steps` steps of `scene` with
/// `kind` from its initial state (on one thread), and whether a guard
/// stopped it first.
fn time_once(scene: &Scene, kind: RotatorKind, steps: u64) -> (f64, f64, bool) {
    let mut w = World::new(scene);
    let (t0, c0) = (Instant::now(), thread_cpu_s());
    kind.visit(Steps(&mut w, steps));
    let (wall, cpu) = (t0.elapsed().as_secs_f64(), thread_cpu_s() - c0);
    black_box(&w.states);
    let done = w.step.max(1);
    let per = done as f64 * scene.bodies.len() as f64;
    (wall / per, cpu / per, done < steps)
}

fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let Some(path) = args
        .iter()
        .enumerate()
        .find(|(i, a)| a.ends_with(".toml") && (*i == 0 || !args[i - 1].starts_with("--")))
        .map(|(_, a)| a.clone())
    else {
        eprintln!("usage: cargo bench --bench contact_rotators -- SCENE.toml [--rotators a,b] [--dt DT] [--steps N] [--rounds R] [--threads T]");
        return;
    };
    let base = scenario::load(std::path::Path::new(&path)).expect("the scene loads");
    // Default: every rotator that runs contact scenes.
    let kinds: Vec<RotatorKind> = match flag("--rotators") {
        None => RotatorKind::ALL
            .into_iter()
            .filter(|k| k.contact_refusal().is_none())
            .collect(),
        Some(l) => l
            .split(',')
            .map(|n| RotatorKind::from_name(n.trim()).expect("a rotator name"))
            .collect(),
    };
    let steps: u64 = flag("--steps").map_or(1000, |s| s.parse().expect("--steps N"));
    let rounds: usize = flag("--rounds").map_or(7, |s| s.parse().expect("--rounds R"));
    let threads: usize = flag("--threads").map_or(1, |s| s.parse().expect("--threads T"));
    let dt: f64 = flag("--dt").map_or(base.sim.dt(), |s| s.parse().expect("--dt DT"));
    let scenes: Vec<Scene> = kinds
        .iter()
        .map(|&k| {
            let mut s = base.clone();
            s.sim = SimParams::with_steps(dt, steps, k, None).expect("dt > 0");
            s
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    println!(
        "{path}: {} bodies, dt = {dt:e} s, {steps} steps per round, {rounds} rounds, {threads} thread(s); load average {}",
        base.bodies.len(),
        loadavg()
    );
    let mut wall: Vec<Vec<f64>> = vec![Vec::new(); kinds.len()];
    let mut cpu: Vec<Vec<f64>> = vec![Vec::new(); kinds.len()];
    let mut stopped = vec![false; kinds.len()];
    // Single-threaded pool: the whole run on one worker, whose CPU time
    // the schedstat of `thread-self` reads.
    pool.install(|| {
        for _ in 0..rounds {
            for (i, (s, &k)) in scenes.iter().zip(&kinds).enumerate() {
                let (w, c, stop) = time_once(s, k, steps);
                wall[i].push(w * 1e9);
                cpu[i].push(c * 1e9);
                stopped[i] |= stop;
            }
        }
    });
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
    };
    let wall_med: Vec<f64> = wall.iter_mut().map(median).collect();
    let cpu_med: Vec<f64> = cpu.iter_mut().map(median).collect();
    let best = cpu_med.iter().copied().fold(f64::INFINITY, f64::min);
    println!("ns per body-step, medians of {rounds} alternated rounds (CPU: this thread's time on a core; wall: elapsed)");
    println!("rotator       CPU median  (min – max)        / fastest   wall median");
    for (i, k) in kinds.iter().enumerate() {
        let c = &cpu[i];
        println!(
            "{:<12}  {:>9.1}  ({:>7.1} – {:<7.1})  {:>8.3}   {:>10.1}{}",
            k.name(),
            cpu_med[i],
            c[0],
            c[c.len() - 1],
            cpu_med[i] / best,
            wall_med[i],
            if stopped[i] {
                "  stopped by a guard: timed up to the stop"
            } else {
                ""
            }
        );
    }
    println!("load average after: {}", loadavg());
}
