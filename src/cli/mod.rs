//! The command line: raw arguments ([`args`]), checked plans ([`plan`]) and
//! the commands that execute them. `main` only parses and maps errors to
//! exit codes.

pub mod args;
pub mod plan;

pub use args::{Cli, Command, EXIT_CODES};

use crate::advice::CheckReport;
use crate::error::{Error, Result};
use crate::integrate::rotate::{rotator_markdown, rotator_table};
use std::io::Write;

/// Execute one command.
pub fn execute(cli: Cli) -> Result<()> {
    if let Some(n) = cli.threads {
        threads(n)?;
    }
    match cli.command {
        Command::Run(args) => run(args.plan()?),
        Command::Check(args) => {
            let p = args.plan()?;
            print(&CheckReport {
                scene: &p.scene,
                advice: &p.advice,
                scene_warnings: &p.warnings,
            })
        }
        Command::Rotators(args) => match args.markdown {
            true => print(&rotator_markdown()),
            false => print(&rotator_table()),
        },
        Command::Keys(args) => match args.markdown {
            true => print(&crate::scenario::keys::keys_markdown()),
            false => print(&crate::scenario::keys::keys_text()),
        },
        Command::Compare(args) => {
            use crate::study::compare::{compare, print_report};
            let (scene, opts) = args.plan()?;
            let report = compare(&scene, &opts)?;
            if opts.progress {
                print_report(&report);
                println!("-> {}", opts.out_dir.display());
            }
            Ok(())
        }
        Command::Converge(args) => {
            use crate::study::converge::{converge, print_report};
            let (scene, opts) = args.plan()?;
            let report = converge(&scene, &opts)?;
            if opts.progress {
                print_report(&report);
                println!("-> {}", opts.out_dir.display());
            }
            Ok(())
        }
        Command::Plot(args) => {
            let out = crate::study::csvplot::plot_files(&crate::study::csvplot::PlotOptions {
                files: args.files,
                out: args.output,
                column: args.column,
                x: args.x,
                log_x: args.log_x,
                log_y: args.log_y,
                signed: args.signed,
            })?;
            println!("{}", out.display());
            Ok(())
        }
        Command::Generate(args) => {
            let quiet = args.quiet;
            let opts = args.plan(command_line())?;
            let r = crate::generate::generate(&opts)?;
            if !quiet {
                println!(
                    "placed {} in {} attempts: volume fraction {:.4} of the region, {:.4} of the box\n-> {} (bodies: {})",
                    crate::generate::counted(r.placed - r.spheres, r.spheres),
                    r.attempts,
                    r.volume_fraction,
                    r.box_fraction,
                    r.scenario.display(),
                    r.body_file.display()
                );
            }
            Ok(())
        }
        Command::Settle(args) => settle(args.plan()?),
        Command::Replicate(args) => {
            let p = args.plan(command_line())?;
            let r = crate::generate::replicate::replicate(&p.scene, &p.opts)?;
            if !p.quiet {
                let [nx, ny, nz] = p.opts.times;
                println!(
                    "{} x {} x {} copies of {}: {} in the box {} .. {}; touching contacts {} (the source: {} each), largest overlap ratio {:.4} (guards.start_overlap_ratio = {})\n-> {} (bodies: {})",
                    nx,
                    ny,
                    nz,
                    p.scene.source,
                    r.written,
                    r.walls.min,
                    r.walls.max,
                    r.touching.1,
                    r.touching.0,
                    r.max_overlap_ratio,
                    r.start_overlap_ratio,
                    r.scenario.display(),
                    r.body_file.display()
                );
            }
            Ok(())
        }
        Command::Render(args) => render(args.plan()?),
        Command::Stress(args) => {
            use crate::study::stress::{print_report, stress};
            let (cases, opts) = args.plan()?;
            let report = stress(cases, &opts)?;
            if opts.progress {
                print_report(&report);
                println!("-> {}", opts.out_dir.display());
            }
            Ok(())
        }
    }
}

/// Size the thread pool (`--threads N`); without the flag rayon's default
/// holds: `RAYON_NUM_THREADS`, else the available cores.
fn threads(n: usize) -> Result<()> {
    if n == 0 {
        return Err(Error::bad(
            "command line",
            "--threads",
            "must be >= 1 (1 runs everything on one thread)",
        ));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global()
        .map_err(|e| Error::bad("command line", "--threads", e.to_string()))
}

/// Write `text` to stdout. A closed pipe (`fibresim rotators | head`) is
/// the reader's choice, not an error: stop quietly.
fn print(text: &dyn std::fmt::Display) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match write!(out, "{text}").and_then(|_| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Error::io("<stdout>", e)),
        _ => Ok(()),
    }
}

/// `fibresim run`: warnings, the resumed outputs, the run, and its summary.
fn run(mut plan: plan::RunPlan) -> Result<()> {
    #[cfg(feature = "mpi")]
    if crate::ranks::launched() {
        let (out_dir, quiet) = (plan.opts.out_dir.clone(), plan.quiet);
        let warnings = plan.warnings.iter().chain(&plan.advice.warnings);
        let job = crate::ranks::Job {
            warnings: warnings.cloned().collect(),
            notes: std::mem::take(&mut plan.notes),
            scene: plan.scene,
            opts: &plan.opts,
            resume: plan.resume.as_ref(),
            quiet,
        };
        return crate::ranks::run(job, |scene, o| print_outcome(scene, o, &out_dir, quiet));
    }
    for w in plan.warnings.iter().chain(&plan.advice.warnings) {
        eprintln!("warning: {w}");
    }
    for n in &plan.notes {
        eprintln!("note: {n}");
    }
    let out_dir = &plan.opts.out_dir;
    // Ctrl-C: finish the current step, write a checkpoint, flush, exit 130.
    let _ = ctrlc::set_handler(|| {
        crate::run::INTERRUPTED.store(true, std::sync::atomic::Ordering::Relaxed)
    });
    // The world takes the step-0 states; the scene keeps no copy.
    let initial = std::mem::take(&mut plan.scene.initial);
    let scene = &plan.scene;
    let resume = plan.resume.as_ref().map(|r| &r.0);
    let n = scene.bodies.len();
    let outcome = on_pool(n, || {
        crate::run::run_from(scene, initial, &plan.opts, resume)
    });
    print_outcome(scene, &outcome, out_dir, plan.quiet);
    outcome.map(|_| ())
}

/// Run `op`, the stepping of `n` bodies, on a thread of the pool when the
/// step runs its stages there ([`parallel`](crate::contact::stage::parallel)):
/// they then start on the thread that waits for them, where from the main
/// thread each was a job handed to the pool and waited for (a wake-up a
/// stage, ~20 a step; the main thread asleep in between). Smaller scenes
/// stay on the main thread and start no pool. (Never around MPI calls:
/// they stay on the main thread.)
fn on_pool<R: Send>(n: usize, op: impl FnOnce() -> R + Send) -> R {
    if crate::contact::stage::parallel(n) {
        rayon::scope(|_| op())
    } else {
        op()
    }
}

/// What `fibresim run` prints of its outcome (the summary's headline, or
/// where the outputs of a stopped run are).
pub(crate) fn print_outcome(
    scene: &crate::scenario::Scene,
    outcome: &Result<crate::output::Summary>,
    out_dir: &std::path::Path,
    quiet: bool,
) {
    match outcome {
        Ok(s) if !quiet => {
            let resumed = match s.first_step {
                0 => String::new(),
                f => format!(
                    " ({} of them in this run, from the checkpoint)",
                    s.steps - f
                ),
            };
            println!(
                "{}: {} steps{resumed} of {:e} s with {} in {:.3} s ({:.1} ns per body-step) -> {}",
                scene.source,
                s.steps,
                s.dt,
                s.rotator,
                s.wall_s,
                s.ns_per_body_step,
                out_dir.display()
            );
            if let (Some(m), Some(f)) = (s.energy_error_full_max_pct, s.energy_error_full_final_pct)
            {
                println!(
                    "energy error (Eq. 65 with elastic energy): max {m:.3e} %, final {f:.3e} %"
                );
            }
            if let Some(o) = s.max_overlap_ratio {
                println!("largest overlap: {o:.3e} D");
            }
            if let Some(e) = s.reference_error_final_rad {
                println!("closed-form reference: final angle error {e:.3e} rad");
            }
        }
        Err(Error::Unstable(_) | Error::Interrupted(_)) => {
            eprintln!("outputs so far kept in {}", out_dir.display())
        }
        _ => {}
    }
}

/// The command line as typed, with the program called `fibresim` (for the
/// header of the files a command writes).
fn command_line() -> String {
    std::iter::once("fibresim".to_string())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ")
}

/// `fibresim settle`: run with damping until the bed is still, then write
/// the settled bed as an elastic scenario and its body file.
fn settle(mut plan: plan::SettlePlan) -> Result<()> {
    for w in &plan.advice.warnings {
        eprintln!("warning: {w}");
    }
    for n in &plan.notes {
        eprintln!("note: {n}");
    }
    let _ = ctrlc::set_handler(|| {
        crate::run::INTERRUPTED.store(true, std::sync::atomic::Ordering::Relaxed)
    });
    let initial = std::mem::take(&mut plan.scene.initial);
    let scene = &plan.scene;
    let resume = plan.resume.as_ref().map(|r| &r.0);
    let n = scene.bodies.len();
    let s = on_pool(n, || {
        crate::run::run_from(scene, initial, &plan.opts, resume)
    })?;
    let settle = plan.opts.settle.expect("a settle plan has a settle test");
    let body_file = crate::generate::body_file_of(&plan.write);
    let n = scene.bodies.len() as f64;
    let spheres = scene
        .bodies
        .iter()
        .filter(|b| matches!(b.shape, crate::body::Shape::Sphere { .. }))
        .count();
    let census = crate::fmt::census(scene.bodies.len() - spheres, spheres);
    let per = if spheres > 0 { "body" } else { "fibre" };
    let (ke, settled) = (s.kinetic_final, s.settled == Some(true));
    let text = crate::scenario::write::BedScenario {
        comment: vec![
            format!("Settled by: {}", command_line()),
            format!(
                "from {} ({census}): {} after {} steps of {:e} s (t = {} s), kinetic energy {:.3e} J per {per} (threshold {:.3e} J).",
                scene.source,
                if settled { "settled" } else { "NOT settled (t_end reached)" },
                s.steps,
                s.dt,
                crate::fmt::short(s.steps as f64 * s.dt),
                ke / n,
                settle.ke_per_body
            ),
            "Elastic (no damping); the resting contacts overlap, hence guards.start_overlap_ratio.".into(),
        ],
        dt: plan.write_dt,
        t_end: plan.write_t_end,
        gravity: scene.gravity,
        walls: scene.walls.as_ref(),
        materials: &scene.materials,
        restitution: None,
        friction: scene.friction,
        start_overlap_ratio: Some(crate::generate::settled_start_overlap(
            s.max_overlap_ratio.unwrap_or(0.0),
        )),
        body_file: &body_file
            .file_name()
            .map_or(String::new(), |f| f.to_string_lossy().into_owned()),
    };
    // The body file was written under a temporary name: both files appear
    // by rename, the body file first, so neither is left without the other.
    let bodies_tmp = crate::output::file::temporary(&body_file);
    let toml_tmp = crate::output::file::temporary(&plan.write);
    let written = std::fs::write(&toml_tmp, text.to_string())
        .map_err(|e| Error::io(&plan.write, e))
        .and_then(|_| {
            std::fs::rename(&bodies_tmp, &body_file).map_err(|e| Error::io(&body_file, e))
        })
        .and_then(|_| {
            std::fs::rename(&toml_tmp, &plan.write).map_err(|e| Error::io(&plan.write, e))
        });
    if written.is_err() {
        let _ = std::fs::remove_file(&bodies_tmp);
        let _ = std::fs::remove_file(&toml_tmp);
    }
    written?;
    if !plan.quiet {
        let resumed = match s.first_step {
            0 => String::new(),
            f => format!(" ({} of them in this run)", s.steps - f),
        };
        println!(
            "{}: {} after {} steps{resumed} of {:e} s in {:.1} s ({:.3e} {per}-steps/s); kinetic energy {:.3e} J per {per} (threshold {:.3e} J), dissipated {:.4e} J\n-> {} (bodies: {}); run outputs in {}",
            scene.source,
            if settled { "settled" } else { "not settled by t_end" },
            s.steps,
            s.dt,
            s.wall_s,
            s.body_steps_per_s(),
            ke / n,
            settle.ke_per_body,
            s.energy_dissipated.unwrap_or(0.0),
            plan.write.display(),
            body_file.display(),
            plan.opts.out_dir.display()
        );
    }
    if settled {
        Ok(())
    } else {
        Err(Error::bad(
            &scene.source,
            "--t-end",
            format!("the bed did not settle by t = {} s (kinetic energy {:.3e} J per body); the unsettled bed was written anyway; give a longer --t-end", crate::fmt::short(s.steps as f64 * s.dt), ke / n),
        ))
    }
}

/// `fibresim render`: a still (PNG) or an animation (GIF).
fn render(p: plan::RenderPlan) -> Result<()> {
    use crate::render::{animate, still, Source};
    let source = Source::open(&p.input, p.scenario.as_deref())?;
    crate::output::create_parent_dir(&p.output, "--out")?;
    if p.gif {
        let n = animate(&source, &p.opts, p.fps, &p.output)?;
        println!("{} ({n} frames)", p.output.display());
    } else {
        let f = still(&source, p.step, &p.opts, &p.output)?;
        println!(
            "{} (step {}, t = {} s)",
            p.output.display(),
            f.step,
            crate::fmt::short(f.t)
        );
    }
    Ok(())
}
