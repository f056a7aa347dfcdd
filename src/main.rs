//! Thin entry point: parse the command line, call the library, map errors to
//! exit codes (see `fibresim::error`).

use clap::Parser;
use fibresim::advice::advise;
use fibresim::cli::{
    CheckArgs, Cli, Command, CompareArgs, ConvergeArgs, PlotArgs, RunArgs, StressArgs,
};
use fibresim::error::{Error, Result};
use fibresim::integrate::rotate::RotatorKind;
use fibresim::output::Checkpoint;
use fibresim::run::{self, RunOptions};
use fibresim::scenario::{self, Scene, SimParams};
use std::path::PathBuf;

/// The default scene of `fibresim run` with no scenario.
const DEFAULT_SCENE: (&str, &str) = (
    "<built-in nine_fibres>",
    include_str!("../scenarios/nine_fibres.toml"),
);

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => cmd_run(args),
        Command::Check(args) => cmd_check(args),
        Command::Rotators => {
            print_rotators();
            Ok(())
        }
        Command::Compare(args) => cmd_compare(args),
        Command::Converge(args) => cmd_converge(args),
        Command::Plot(args) => cmd_plot(args),
        Command::Stress(args) => cmd_stress(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}

fn print_rotators() {
    let kinds = RotatorKind::SELECTABLE;
    let w = kinds
        .iter()
        .map(|k| k.info().equations.len())
        .max()
        .unwrap_or(0);
    println!(
        "{:<11} {:<w$} {:>5} {:>5}  scheme",
        "name", "equations", "order", "evals"
    );
    for k in kinds {
        let i = k.info();
        println!(
            "{:<11} {:<w$} {:>5} {:>5}  {}",
            i.name, i.equations, i.order, i.torque_evals, i.title
        );
        println!("{:11} prescribed torque: {}", "", i.torque_contract);
        println!("{:11} contact torque:    {}", "", i.contact_contract);
    }
    println!("\norder: measured global order for a general load (tests/rotator_order.rs); evals: torque evaluations per step");
}

fn load_scene(args: &RunArgs) -> Result<(Scene, String)> {
    let (mut scene, stem) = match &args.scenario {
        Some(p) => {
            let stem = p
                .file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
            (scenario::load(p)?, stem)
        }
        None => (
            scenario::parse_str(DEFAULT_SCENE.1, DEFAULT_SCENE.0)?,
            "default".to_string(),
        ),
    };
    if args.rotator.is_some() || args.dt.is_some() || args.t_end.is_some() || args.every.is_some() {
        let s = &scene.sim;
        scene.sim = SimParams::new(
            args.dt.unwrap_or(s.dt()),
            args.t_end.unwrap_or(s.t_end()),
            args.rotator.unwrap_or(s.rotator()),
            args.every.or(s.every()),
            "command line",
            "--",
        )?;
    }
    if let Some(v) = args.max_energy_error {
        scene.guards.energy_error_pct = positive_flag("--max-energy-error", v)?;
    }
    if let Some(v) = args.max_overlap {
        scene.guards.overlap_ratio = positive_flag("--max-overlap", v)?;
    }
    Ok((scene, stem))
}

fn positive_flag(flag: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::bad(
            "command line",
            flag,
            format!("must be a finite number > 0, got {v}"),
        ))
    }
}

fn cmd_check(args: CheckArgs) -> Result<()> {
    let mut scene = scenario::load(&args.scenario)?;
    if let Some(dt) = args.dt {
        let s = &scene.sim;
        scene.sim = SimParams::new(dt, s.t_end(), s.rotator(), s.every(), "command line", "--")?;
    }
    let a = advise(&scene);
    println!(
        "scenario {}: {} bodies, dt = {:e} s, {} steps, rotator {}",
        scene.source,
        scene.bodies.len(),
        scene.sim.dt(),
        scene.sim.steps(),
        scene.sim.rotator()
    );
    println!("\nbodies (mass kg; principal inertia kg m^2, body x y z):");
    for (i, b) in scene.bodies.iter().enumerate() {
        let p = b.inertia.principal;
        println!(
            "  [{i}] {:<10} {:?}  m = {:.4e}  I = ({:.4e}, {:.4e}, {:.4e})",
            scene.names[i], b.shape, b.mass, p.x, p.y, p.z
        );
    }
    println!("\ncomponents: gravity {}, walls {}, contact search {}, prescribed torques on {} bodies, closed-form reference {}",
        if scene.gravity.is_some() { "on" } else { "off" },
        if scene.walls.is_some() { "6 half-spaces" } else { "none" },
        match scene.bodies.len() { _ if !scene.needs_contacts() => "off".to_string(), 1 => "walls only".into(), n if n <= 32 => format!("{n} bodies, all pairs"), n => format!("{n} bodies, sort-and-sweep") },
        scene.torques.len(),
        if scene.reference.is_some() { "yes" } else { "no" });
    if !a.pairs.is_empty() {
        println!("\nimpact speeds bounded by energy conservation: E_avail = {:.4e} J (all of it into one body)", a.available_energy);
        println!("m* = effective mass at the worst contact point: 1/m_eff = 1/m + |r x n|^2 / I_transverse, lever arm");
        println!("  |r x n| = max(D/2, L/2) (a fibre's end hit along its side normal); a pair sums 1/m_eff of its bodies");
        println!("  and their bounds v_max = sqrt(2 E_avail / m_eff); m_trans = the translational mass alone, for comparison;");
        println!("  t_tilt = period of an end face rocking on the contact under the peak force of that impact");
        println!(
            "  {:<24} {:>11} {:>12} {:>11} {:>13} {:>13} {:>14}",
            "pair",
            "m* (kg)",
            "m_trans (kg)",
            "v_max (m/s)",
            "t_Hertz (s)",
            "t_tilt (s)",
            "t_Rayleigh (s)"
        );
        for p in &a.pairs {
            println!(
                "  {:<24} {:>11.4e} {:>12.4e} {:>11.4e} {:>13.4e} {:>13.4e} {:>14.4e}",
                p.pair,
                p.reduced_mass,
                p.translational_mass,
                p.v_max,
                p.contact_time,
                p.tilt_period,
                p.rayleigh_time
            );
        }
    }
    match a.recommended_dt {
        Some(r) => println!("\nrecommended dt <= {r:.3e} s (shortest collision / 50, fastest face tilt / 50, and 0.2 x Rayleigh time); chosen dt = {:e} s, margin {:.3}x", scene.sim.dt(), r / scene.sim.dt()),
        None => println!("\nno contacts to resolve: dt is limited by accuracy only (see `fibresim rotators` for orders)"),
    }
    if a.recommended_dt.is_some() {
        let i = scene.sim.rotator().info();
        println!(
            "note: the advice resolves the contact mechanics; the rotator's own error on contact torques comes on top. {}: {}.{}",
            i.name,
            i.contact_contract,
            if i.closing_kick {
                ""
            } else {
                " That is first order in dt: its energy error per collision falls only like dt (README, test case 1; `fibresim stress` for stiff impacts)"
            }
        );
    }
    for w in &a.warnings {
        println!("warning: {w}");
    }
    Ok(())
}

fn cmd_run(args: RunArgs) -> Result<()> {
    let checkpoint = args.resume.as_deref().map(Checkpoint::read).transpose()?;
    let (scene, stem) = match &checkpoint {
        Some(c) => (
            run::scene_from_checkpoint(c, args.t_end)?,
            "resumed".to_string(),
        ),
        None => load_scene(&args)?,
    };
    if args.checkpoint_every == Some(0) {
        return Err(Error::bad(
            "command line",
            "--checkpoint-every",
            "must be >= 1",
        ));
    }
    let advice = advise(&scene);
    if let Some(limit) = advice.hard_limit_dt {
        if scene.sim.dt() > limit && !args.allow_large_dt {
            return Err(Error::bad(
                &scene.source,
                "simulation.dt",
                format!(
                    "dt = {:e} s leaves fewer than 5 steps for the shortest Hertz collision or face-tilt period ({:.3e} s); use dt <= {:.3e} s (see `fibresim check`), or --allow-large-dt to run anyway",
                    scene.sim.dt(),
                    limit * 5.0,
                    advice.recommended_dt.unwrap_or(limit)
                ),
            ));
        }
    }
    for w in &advice.warnings {
        eprintln!("warning: {w}");
    }
    // The checkpoint's folder ("." for a bare `checkpoint.json`).
    let checkpoint_dir = args.resume.as_ref().map(|p| {
        p.parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), PathBuf::from)
    });
    let default_out = match &checkpoint_dir {
        Some(d) => d.clone(),
        None => PathBuf::from("out")
            .join(&stem)
            .join(scene.sim.rotator().name()),
    };
    let out_dir = args.out.clone().unwrap_or(default_out);
    if let (Some(c), Some(from)) = (&checkpoint, &checkpoint_dir) {
        run::copy_resume_outputs(c, from, &out_dir)?;
    }
    let opts = RunOptions {
        out_dir: out_dir.clone(),
        progress: !args.quiet,
        checkpoint_every: args.checkpoint_every,
    };
    // Ctrl-C: finish the current step, write a checkpoint, flush, exit 130.
    let _ =
        ctrlc::set_handler(|| run::INTERRUPTED.store(true, std::sync::atomic::Ordering::Relaxed));
    let outcome = run::run_from(&scene, &opts, checkpoint.as_ref());
    match &outcome {
        Ok(o) if !args.quiet => {
            let s = o;
            println!(
                "{}: {} steps of {:e} s with {} in {:.3} s ({:.1} ns per body-step) -> {}",
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
    outcome.map(|_| ())
}

fn study_scene(path: &std::path::Path, sub: &str) -> Result<(Scene, PathBuf)> {
    let stem = path
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    Ok((
        scenario::load(path)?,
        PathBuf::from("out").join(stem).join(sub),
    ))
}

fn cmd_compare(args: CompareArgs) -> Result<()> {
    use fibresim::study::compare::{compare, print_report, CompareOptions};
    let (scene, default_out) = study_scene(&args.scenario, "compare")?;
    let opts = CompareOptions {
        rotators: fibresim::study::parse_rotators(Some(&args.rotators))?,
        dt: args.dt,
        t_end: args.t_end,
        out_dir: args.out.unwrap_or(default_out),
        progress: !args.quiet,
    };
    let report = compare(&scene, &opts)?;
    if !args.quiet {
        print_report(&report);
        println!("-> {}", opts.out_dir.display());
    }
    Ok(())
}

fn cmd_converge(args: ConvergeArgs) -> Result<()> {
    use fibresim::study::converge::{converge, print_report, ConvergeOptions};
    let (scene, default_out) = study_scene(&args.scenario, "converge")?;
    let opts = ConvergeOptions {
        rotators: fibresim::study::parse_rotators(Some(&args.rotators))?,
        dt_max: args.dt_max,
        dt_min: args.dt_min,
        points: args.points,
        t_end: args.t_end,
        ref_factor: args.ref_factor,
        out_dir: args.out.unwrap_or(default_out),
        progress: !args.quiet,
    };
    let report = converge(&scene, &opts)?;
    if !args.quiet {
        print_report(&report);
        println!("-> {}", opts.out_dir.display());
    }
    Ok(())
}

fn cmd_plot(args: PlotArgs) -> Result<()> {
    let out = fibresim::study::csvplot::plot_files(&fibresim::study::csvplot::PlotOptions {
        files: args.files,
        out: args.output,
        column: args.column,
        x: args.x,
        log_x: args.log_x,
        log_y: args.log_y,
    })?;
    println!("{}", out.display());
    Ok(())
}

fn cmd_stress(args: StressArgs) -> Result<()> {
    use fibresim::study::stress::{load_cases, print_report, stress, StressOptions};
    let factors = args
        .factors
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<f64>().map_err(|_| {
                Error::bad(
                    "command line",
                    "--factors",
                    format!("{s:?} is not a number; give e.g. 0.25,1,4,16"),
                )
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let opts = StressOptions {
        rotators: fibresim::study::parse_rotators(Some(&args.rotators))?,
        factors,
        energy_tol_pct: positive_flag("--energy-tol", args.energy_tol)?,
        outcome_tol_pct: positive_flag("--outcome-tol", args.outcome_tol)?,
        out_dir: args.out,
        progress: !args.quiet,
    };
    let report = stress(load_cases(&args.dir, &args.cases)?, &opts)?;
    if !args.quiet {
        print_report(&report);
        println!("-> {}", opts.out_dir.display());
    }
    Ok(())
}
