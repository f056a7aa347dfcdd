//! Thin entry point: parse the command line, call the library, map errors to
//! exit codes (see `fibresim::error`).

use clap::Parser;
use fibresim::cli::{Cli, Command, CompareArgs, ConvergeArgs, PlotArgs, RunArgs};
use fibresim::error::{Error, Result};
use fibresim::integrate::rotate::RotatorKind;
use fibresim::run::{run, RunOptions};
use fibresim::scenario::{self, Scene, SimParams};
use std::path::PathBuf;

/// The default scene of `fibresim run` with no scenario.
const DEFAULT_SCENE: (&str, &str) = (
    "<built-in torque_fibre>",
    include_str!("../scenarios/torque_fibre.toml"),
);

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => cmd_run(args),
        Command::Rotators => {
            print_rotators();
            Ok(())
        }
        Command::Compare(args) => cmd_compare(args),
        Command::Converge(args) => cmd_converge(args),
        Command::Plot(args) => cmd_plot(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}

fn print_rotators() {
    println!(
        "{:<11} {:<16} {:>5} {:>6}  torque contract",
        "name", "equations", "order", "evals"
    );
    for k in RotatorKind::ALL {
        let i = k.info();
        println!(
            "{:<11} {:<16} {:>5} {:>6}  {}",
            i.name, i.equations, i.order, i.torque_evals, i.torque_contract
        );
    }
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
            args.dt.unwrap_or(s.dt),
            args.t_end.unwrap_or(s.t_end()),
            args.rotator.unwrap_or(s.rotator),
            args.every.or(s.every),
            "command line",
            "--",
        )?;
    }
    Ok((scene, stem))
}

fn cmd_run(args: RunArgs) -> Result<()> {
    let (scene, stem) = load_scene(&args)?;
    let out_dir = args.out.clone().unwrap_or_else(|| {
        PathBuf::from("out")
            .join(&stem)
            .join(scene.sim.rotator.name())
    });
    let opts = RunOptions {
        out_dir: out_dir.clone(),
        every: None,
        progress: !args.quiet,
    };
    let outcome = run(&scene, &opts);
    match &outcome {
        Ok(o) if !args.quiet => {
            let s = &o.summary;
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
            if let (Some(m), Some(f)) = (s.energy_error_max_pct, s.energy_error_final_pct) {
                println!("energy error (Eq. 65): max {m:.3e} %, final {f:.3e} %");
            }
            if let Some(e) = s.reference_error_final_rad {
                println!("closed-form reference: final angle error {e:.3e} rad");
            }
        }
        Err(Error::Unstable(_)) => eprintln!("outputs so far kept in {}", out_dir.display()),
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
