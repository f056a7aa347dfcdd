//! The study commands: `compare`, `converge`, `plot`. Short runs only.

use crate::common;

use fibresim::integrate::rotate::RotatorKind;
use std::path::Path;
use std::process::{Command, Output};

fn fibresim(args: &[&str], threads: Option<usize>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_fibresim"));
    c.args(args).current_dir(env!("CARGO_MANIFEST_DIR"));
    if let Some(n) = threads {
        c.env("RAYON_NUM_THREADS", n.to_string());
    }
    c.output().expect("binary runs")
}

fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "exit {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Header and rows of a CSV file, checking every row has the header's width.
fn csv(p: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let h: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let rows: Vec<Vec<String>> = r
        .records()
        .map(|x| x.unwrap().iter().map(String::from).collect())
        .collect();
    for row in &rows {
        assert_eq!(row.len(), h.len(), "{}", p.display());
    }
    (h, rows)
}

fn col(h: &[String], rows: &[Vec<String>], name: &str) -> Vec<String> {
    let i = h
        .iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no {name}"));
    rows.iter().map(|r| r[i].clone()).collect()
}

/// A chart PNG of the documented size in which the first series is drawn
/// (its palette colour, Okabe–Ito blue, occurs).
fn is_png(p: &Path) {
    let b = std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let mut reader = png::Decoder::new(std::io::Cursor::new(b))
        .read_info()
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let mut rgb = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut rgb).unwrap();
    assert_eq!(
        (info.width, info.height),
        (fibresim::plot::WIDTH, fibresim::plot::HEIGHT),
        "{}",
        p.display()
    );
    assert!(
        rgb[..info.buffer_size()]
            .chunks(3)
            .any(|c| c == [0x00, 0x72, 0xB2]),
        "{}: no series drawn",
        p.display()
    );
}

fn svg_with(p: &Path, labels: &[&str]) {
    let s = std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    assert!(s.contains("<svg"), "{}", p.display());
    for l in labels {
        assert!(s.contains(l), "{} lacks label {l}", p.display());
    }
}

/// Test case 1's fibre spinning free: no torque, no contact, no reference.
fn free_spin() -> String {
    format!(
        "[simulation]\ndt = 1e-4\nt_end = 0.02\n[[body]]{}{}",
        common::FIBRE,
        "position = [0.0, 0.0, 0.0]\naxis = [0.6, 0.8, 0.0]\nangular_velocity = [40.0, 25.0, -10.0]\n"
    )
}
#[test]
fn converge_torque_fibre_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let o = fibresim(
        &[
            "converge",
            "scenarios/torque_fibre.toml",
            "--t-end",
            "0.01",
            "--dt-max",
            "1e-4",
            "--dt-min",
            "1e-5",
            "--points",
            "3",
            "--ref-factor",
            "4",
            "--rotators",
            "pcdm,euler",
            "--out",
            out,
        ],
        None,
    );
    ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("Richardson"), "{stdout}");
    let (h, rows) = csv(&dir.path().join("convergence.csv"));
    assert_eq!(
        h,
        [
            "rotator",
            "dt",
            "steps",
            "alpha_rad",
            "geodesic_rad",
            "x_error_pct",
            "position_error_m",
            "energy_error_full_max_pct",
            "energy_error_full_final_pct",
            "energy_error_max_pct",
            "energy_error_final_pct",
            "wall_s",
            "timing_runs",
            "stopped"
        ]
    );
    assert_eq!(rows.len(), 2 * 3, "2 rotators x 3 step sizes");
    // Timed in the sequential pass: short runs are repeated (median).
    for (w, n) in col(&h, &rows, "wall_s")
        .iter()
        .zip(col(&h, &rows, "timing_runs"))
    {
        assert!(w.parse::<f64>().unwrap() > 0.0);
        assert!(n.parse::<u32>().unwrap() >= 3, "{n}");
    }
    assert!(stdout.contains("none concurrent"), "{stdout}");
    // Each δt divides the end time exactly.
    for (dt, steps) in col(&h, &rows, "dt").iter().zip(col(&h, &rows, "steps")) {
        let dt: f64 = dt.parse().unwrap();
        let n: f64 = steps.parse().unwrap();
        assert!((dt * n - 0.01).abs() < 1e-12);
    }
    for a in col(&h, &rows, "alpha_rad") {
        assert!(a.parse::<f64>().unwrap() > 0.0);
    }
    let (h, rows) = csv(&dir.path().join("orders.csv"));
    assert_eq!(rows.len(), 2 * 2, "2 rotators x 2 metrics");
    let orders = col(&h, &rows, "order");
    let pcdm: f64 = orders[0].parse().unwrap();
    assert!((pcdm - 2.0).abs() < 0.3, "pcdm order {pcdm}");
    let (h, rows) = csv(&dir.path().join("reference.csv"));
    assert_eq!(col(&h, &rows, "kind"), ["rk4"]);
    for stem in ["convergence", "convergence_geodesic", "work_precision"] {
        is_png(&dir.path().join(format!("{stem}.png")));
        svg_with(&dir.path().join(format!("{stem}.svg")), &["pcdm", "euler"]);
    }
    svg_with(
        &dir.path().join("convergence.svg"),
        &["slope 1", "slope 2", "Richardson"],
    );
    svg_with(&dir.path().join("work_precision.svg"), &["timed alone"]);
}

/// Contact scenes are measured on the conserved budget (Eq. 65 with the
/// elastic energy). In the coaxial end-on impact nothing rotates, so every
/// rotator gives velocity Verlet's energy error: small, and second order.
/// Plain Eq. 65 would report the elastic dip (~99 % mid-contact) instead.
#[test]
fn converge_contact_scene_uses_full_energy_budget() {
    let dir = tempfile::tempdir().unwrap();
    let o = fibresim(
        &[
            "converge",
            "scenarios/stress/coaxial.toml",
            "--rotators",
            "pcdm,leapfrog",
            "--points",
            "3",
            "--out",
            dir.path().to_str().unwrap(),
        ],
        None,
    );
    ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("elastic energy"), "{stdout}");
    let (h, rows) = csv(&dir.path().join("convergence.csv"));
    let full: Vec<f64> = col(&h, &rows, "energy_error_full_max_pct")
        .iter()
        .map(|x| x.parse().unwrap())
        .collect();
    let plain: Vec<f64> = col(&h, &rows, "energy_error_max_pct")
        .iter()
        .map(|x| x.parse().unwrap())
        .collect();
    let dts: Vec<f64> = col(&h, &rows, "dt")
        .iter()
        .map(|x| x.parse().unwrap())
        .collect();
    // Symmetric head-on: at the deepest compression both fibres stop, so all
    // their kinetic energy is elastic and plain Eq. 65 misses nearly 100 %.
    for p in &plain {
        assert!(*p > 90.0, "plain Eq. 65 sees the elastic dip: {p}");
    }
    // Velocity Verlet is second order: between neighbouring step sizes of a
    // rotator (3 per rotator, largest first) the full budget's error falls
    // as δt², not as the plain error, which stays at the dip.
    for k in (0..rows.len()).filter(|k| k % 3 != 2) {
        let order = (full[k] / full[k + 1]).ln() / (dts[k] / dts[k + 1]).ln();
        assert!(
            (order - 2.0).abs() < 0.5,
            "rows {k}, {}: order {order}",
            k + 1
        );
    }
    let (h, rows) = csv(&dir.path().join("orders.csv"));
    for (m, order) in col(&h, &rows, "metric").iter().zip(col(&h, &rows, "order")) {
        if m == "energy_error_full_max_pct" {
            let order: f64 = order.parse().unwrap();
            assert!((order - 2.0).abs() < 0.2, "Verlet is second order: {order}");
        } else {
            assert_eq!(m, "energy_error_full_final_pct");
        }
    }
    svg_with(
        &dir.path().join("convergence.svg"),
        &["Eq. 65 with elastic energy", "pcdm", "leapfrog"],
    );
}

#[test]
fn converge_closed_form_and_energy_scenes() {
    // Test case 3: closed form, with Table 2's x-error.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    ok(&fibresim(
        &[
            "converge",
            "scenarios/torque_sphere.toml",
            "--t-end",
            "0.1",
            "--dt-max",
            "1e-3",
            "--dt-min",
            "1e-4",
            "--points",
            "3",
            "-q",
            "--out",
            out,
        ],
        None,
    ));
    let (h, rows) = csv(&dir.path().join("convergence.csv"));
    assert_eq!(
        rows.len(),
        RotatorKind::ALL.len() * 3,
        "every scheme by default, 3 step sizes"
    );
    for x in col(&h, &rows, "x_error_pct") {
        assert!(x.parse::<f64>().unwrap().is_finite());
    }
    is_png(&dir.path().join("convergence_x_error.png"));

    // No torque, no reference: the Eq. 65 energy error.
    let scene = dir.path().join("spin.toml");
    std::fs::write(&scene, free_spin()).unwrap();
    let out2 = dir.path().join("spin");
    ok(&fibresim(
        &[
            "converge",
            scene.to_str().unwrap(),
            "--points",
            "3",
            "-q",
            "--out",
            out2.to_str().unwrap(),
        ],
        None,
    ));
    let (h, rows) = csv(&out2.join("convergence.csv"));
    for (a, e) in
        col(&h, &rows, "alpha_rad")
            .iter()
            .zip(col(&h, &rows, "energy_error_full_max_pct"))
    {
        assert!(a.is_empty());
        assert!(e.parse::<f64>().unwrap() >= 0.0);
    }
    is_png(&out2.join("convergence.png"));
}

/// `converge --trajectory`: on a contact scene, each run's end state against
/// a fine run of the named rotator. Ten fibres dropped onto the floor of a
/// box (the first impacts, 0.03 s): `pcdm` takes the start-of-step contact
/// torque (first order, its stated contract), `omelyan` closes each step
/// with the torque of the new configuration (second order, as velocity
/// Verlet's translation), and both orders show in the distance and the
/// angle; the reference's own error (the distance to its twin at twice its
/// step) lies below every measured error. On a torque scene the flag is bad
/// input.
#[test]
fn converge_trajectory_error_on_a_contact_scene() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("drop.toml");
    ok(&fibresim(
        &[
            "generate",
            "--n",
            "10",
            "--diameter",
            "0.01",
            "--length",
            "0.03",
            "--box",
            "0.06,0.06,0.06",
            "--t-end",
            "0.03",
            "--dt",
            "4e-6",
            "-q",
            "-o",
            scene.to_str().unwrap(),
        ],
        None,
    ));
    let out = dir.path().join("cv");
    ok(&fibresim(
        &[
            "converge",
            scene.to_str().unwrap(),
            "--rotators",
            "pcdm,omelyan",
            "--points",
            "3",
            "--dt-max",
            "4e-6",
            "--dt-min",
            "1e-6",
            "--ref-factor",
            "4",
            "--trajectory",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    ));
    let (h, rows) = csv(&out.join("reference.csv"));
    assert_eq!(col(&h, &rows, "kind"), ["nosquish"]);
    let own: f64 = col(&h, &rows, "richardson_position_m")[0].parse().unwrap();
    assert!(own > 0.0);
    let (h, rows) = csv(&out.join("convergence.csv"));
    for p in col(&h, &rows, "position_error_m") {
        assert!(
            p.parse::<f64>().unwrap() > 3.0 * own,
            "{p} m against the reference's {own} m"
        );
    }
    let (h, rows) = csv(&out.join("orders.csv"));
    let order = |rotator: &str, metric: &str| -> f64 {
        let (r, m, o) = (
            col(&h, &rows, "rotator"),
            col(&h, &rows, "metric"),
            col(&h, &rows, "order"),
        );
        (0..rows.len())
            .find(|&i| r[i] == rotator && m[i] == metric)
            .map(|i| o[i].parse().unwrap())
            .unwrap_or_else(|| panic!("no {metric} order for {rotator}"))
    };
    for metric in ["position_error_m", "geodesic_rad"] {
        let (p, o) = (order("pcdm", metric), order("omelyan", metric));
        assert!((0.8..1.2).contains(&p), "pcdm {metric} order {p}");
        assert!((1.8..2.5).contains(&o), "omelyan {metric} order {o}");
    }
    for stem in [
        "convergence_position",
        "convergence_geodesic",
        "work_precision_position",
    ] {
        svg_with(&out.join(format!("{stem}.svg")), &["pcdm", "omelyan"]);
    }
    svg_with(
        &out.join("convergence_position.svg"),
        &["nosquish reference&apos;s own error"],
    );

    let o = fibresim(
        &[
            "converge",
            "scenarios/torque_fibre.toml",
            "--trajectory",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--trajectory"));
}

/// `compare` writes the same per-run files and figure with 1 and 2 threads.
/// compare.csv holds wall times, so it is checked for shape only.
#[test]
fn compare_is_deterministic_across_thread_counts() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("spin.toml");
    std::fs::write(&scene, free_spin()).unwrap();
    let cases = [
        ("scenarios/torque_fibre.toml", "0.005", "1e-5"),
        ("scenarios/torque_sphere.toml", "0.1", "1e-3"),
        (scene.to_str().unwrap(), "0.02", "1e-4"),
    ];
    for (k, (scenario, t_end, dt)) in cases.iter().enumerate() {
        let run = |threads: usize| {
            let out = dir.path().join(format!("c{k}_{threads}"));
            ok(&fibresim(
                &[
                    "compare",
                    scenario,
                    "--rotators",
                    "all",
                    "--t-end",
                    t_end,
                    "--dt",
                    dt,
                    "-q",
                    "--out",
                    out.to_str().unwrap(),
                ],
                Some(threads),
            ));
            out
        };
        let (a, b) = (run(1), run(2));
        let (h, rows) = csv(&a.join("compare.csv"));
        assert_eq!(rows.len(), RotatorKind::ALL.len(), "{scenario}");
        assert_eq!(
            h,
            [
                "rotator",
                "metric",
                "max_error",
                "final_error",
                "wall_s",
                "ns_per_body_step",
                "stopped"
            ]
        );
        assert_eq!(col(&h, &rows, "max_error"), {
            let (h2, r2) = csv(&b.join("compare.csv"));
            col(&h2, &r2, "max_error")
        });
        // The figure is named by what it plots.
        let fig = [
            "angle_error_rk4",
            "angle_error_closed_form",
            "energy_error_full",
        ][k];
        assert!(!a.join("energy_error.png").exists());
        let mut files = vec![format!("{fig}.svg")];
        for r in col(&h, &rows, "rotator") {
            files.push(format!("{r}/energy.csv"));
            if k < 2 {
                files.push(format!("{r}/orientation.csv"));
            }
        }
        for f in &files {
            let (x, y) = (
                std::fs::read(a.join(f)).unwrap(),
                std::fs::read(b.join(f)).unwrap(),
            );
            assert!(x == y, "{scenario}: {f} differs between 1 and 2 threads");
        }
        is_png(&a.join(format!("{fig}.png")));
        svg_with(&a.join(format!("{fig}.svg")), &["pcdm", "leapfrog", "rk4"]);
    }
}

#[test]
fn compare_reports_unstable_runs() {
    // scalar stops at the tan pole when |ω|δt/2 reaches π/2: 2000 rad/s, δt = 2e-3.
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("fast.toml");
    std::fs::write(
        &scene,
        free_spin()
            .replace("[40.0, 25.0, -10.0]", "[2000.0, 0.0, 0.0]")
            .replace("dt = 1e-4", "dt = 2e-3"),
    )
    .unwrap();
    let out = dir.path().join("c");
    let o = fibresim(
        &[
            "compare",
            scene.to_str().unwrap(),
            "--rotators",
            "scalar,pcdm",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    );
    ok(&o);
    let (h, rows) = csv(&out.join("compare.csv"));
    let stopped = col(&h, &rows, "stopped");
    assert!(stopped[0].contains("scalar"), "{stopped:?}");
    // At ‖ω‖δt = 4 rad pcdm does not hit a pole, but its energy error may trip
    // the energy guard; either way it is not the scalar diagnosis.
    assert!(!stopped[1].contains("scalar"), "{stopped:?}");
}

#[test]
fn plot_command() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    ok(&fibresim(
        &[
            "compare",
            "scenarios/torque_sphere.toml",
            "--t-end",
            "0.05",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    ));
    let png = dir.path().join("p.png");
    let svg = dir.path().join("p.svg");
    let e1 = out.join("pcdm/energy.csv");
    let e2 = out.join("euler/energy.csv");
    let (e1, e2) = (e1.to_str().unwrap(), e2.to_str().unwrap());
    ok(&fibresim(
        &[
            "plot",
            e1,
            e2,
            "--column",
            "e_rot",
            "-o",
            png.to_str().unwrap(),
        ],
        None,
    ));
    is_png(&png);
    let o1 = out.join("pcdm/orientation.csv");
    let o2 = out.join("scalar/orientation.csv");
    ok(&fibresim(
        &[
            "plot",
            o1.to_str().unwrap(),
            o2.to_str().unwrap(),
            "--log-y",
            "-o",
            svg.to_str().unwrap(),
        ],
        None,
    ));
    // Axes carry units; --log-y forces the log axis (decade labels).
    svg_with(
        &svg,
        &[
            "pcdm",
            "scalar",
            "err_rad: geodesic angle to the reference (rad)",
            "t: time (s)",
            "10⁻",
        ],
    );
    // Without flags: the energy of the sphere under e^t torque grows over
    // decades, so y is log; t is a linear grid, so x stays linear.
    let auto = dir.path().join("auto.svg");
    ok(&fibresim(
        &[
            "plot",
            e1,
            "--column",
            "e_rot",
            "-o",
            auto.to_str().unwrap(),
        ],
        None,
    ));
    svg_with(&auto, &["e_rot (J)", "t: time (s)", "10⁻"]);
    // compare.csv: max_error takes its unit from the metric column.
    let lin = dir.path().join("table.svg");
    let table = out.join("compare.csv");
    ok(&fibresim(
        &[
            "plot",
            table.to_str().unwrap(),
            "--x",
            "wall_s",
            "-o",
            lin.to_str().unwrap(),
        ],
        None,
    ));
    svg_with(&lin, &["max_error (rad)", "wall_s: wall time (s)"]);
    let missing_col = fibresim(&["plot", e1, "--column", "nope"], None);
    assert_eq!(missing_col.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&missing_col.stderr).contains("e_rot"));
    let missing_file = fibresim(&["plot", "no/such.csv"], None);
    assert_eq!(missing_file.status.code(), Some(2));
    let bad_x = fibresim(&["plot", e1, "--x", "nope"], None);
    assert_eq!(bad_x.status.code(), Some(2));
}

/// The automatic log axis: data spread over decades, not linear grids.
#[test]
fn plot_axis_goes_log_when_data_span_decades() {
    use fibresim::study::csvplot::wants_log;
    let grid: Vec<f64> = (0..=2000).map(|i| i as f64 * 1e-3).collect();
    assert!(!wants_log(&grid), "t = 0, 1e-3, ..., 2: linear");
    let dts = [1e-5, 3.2e-6, 1e-6, 3.2e-7, 1e-7];
    assert!(wants_log(&dts), "a geometric dt sequence over 2 decades");
    let growth: Vec<f64> = (0..100).map(|i| (0.1 * i as f64).exp()).collect();
    assert!(wants_log(&growth), "e^t over 4.3 decades");
    assert!(!wants_log(&[1.0, 10.0, 50.0]), "under 2 decades");
    assert!(!wants_log(&[-1.0, 1e-6, 1.0]), "a negative value");
    assert!(!wants_log(&[0.0, f64::NAN, 1.0]), "one positive value");
}

/// converge's default rotator set (for `src/cli.rs`) is every scheme, so the
/// work-precision figure shows each one.
#[test]
fn converge_default_rotators_are_all_schemes() {
    use fibresim::study::{converge::DEFAULT_ROTATORS, parse_rotators};
    assert_eq!(
        parse_rotators(Some(DEFAULT_ROTATORS)).unwrap(),
        RotatorKind::ALL.to_vec()
    );
}

#[test]
fn bad_rotator_list_is_bad_input() {
    let o = fibresim(
        &[
            "compare",
            "scenarios/torque_sphere.toml",
            "--rotators",
            "pcdm,nope",
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(2));
}
