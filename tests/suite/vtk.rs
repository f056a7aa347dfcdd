//! The VTK time series: every file written is read back (the
//! `.pvd` and each frame's XML by an XML parser, the appended zlib blocks by
//! the library's reader) and its fields, values and times checked against
//! the run's own other outputs: `trajectory.csv` (the exact f64 state, so
//! each Float32 must be its rounding), `summary.json`, and closed forms
//! (end points `x ± L/2 R(q)eₓ`, speed, kinetic energy). A split run
//! resumed from a checkpoint writes the same bytes; the VTK library itself
//! checks a series through `scripts/check_vtk.py` when it is installed.

use crate::common;
use common::{fibresim, ok, resume_to};

use fibresim::output::vtk::read::{read_pvd, read_vtp, Vtp};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

fn nine(dir: &Path, extra: &[&str]) -> PathBuf {
    let out = dir.join("o");
    let mut a = vec![
        "run",
        "scenarios/nine_fibres.toml",
        "--t-end",
        "0.02",
        "--vtk-every",
        "40000",
        "--trajectory-every",
        "40000",
        "--every",
        "20000",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ];
    a.extend(extra);
    ok(fibresim(&a));
    out
}

/// Trajectory rows by (step, body): the 13 state numbers after `body`.
fn trajectory(out: &Path) -> HashMap<(u64, u64), Vec<f64>> {
    let mut r = csv::Reader::from_path(out.join("trajectory.csv")).unwrap();
    r.records()
        .map(|rec| {
            let rec = rec.unwrap();
            let v: Vec<f64> = rec.iter().map(|s| s.parse().unwrap()).collect();
            ((v[0] as u64, v[2] as u64), v[3..].to_vec())
        })
        .collect()
}

/// The XML head of a frame (the appended block cut out) must parse.
/// Whether the file says it is zlib-compressed.
fn xml_head(path: &Path) -> bool {
    let bytes = std::fs::read(path).unwrap();
    let mark = b"<AppendedData encoding=\"raw\">\n_";
    let at = bytes.windows(mark.len()).position(|w| w == mark).unwrap() + mark.len() - 1;
    let mut head = String::from_utf8(bytes[..at].to_vec()).unwrap();
    head.push_str("\n</AppendedData>\n</VTKFile>\n");
    let doc =
        roxmltree::Document::parse(&head).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    doc.root_element().attribute("compressor") == Some("vtkZLibDataCompressor")
}

fn rot_x(q: [f64; 4]) -> [f64; 3] {
    let [w, x, y, z] = q;
    [
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y + w * z),
        2.0 * (x * z - w * y),
    ]
}

/// R(q)ᵀ v: a world vector in the body frame (rotation matrix, not the library).
fn to_body(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let [w, x, y, z] = q;
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    [0, 1, 2].map(|j| (0..3).map(|i| r[i][j] * v[i]).sum())
}

fn close32(a: f64, b: f64, what: &str) {
    assert!(
        (a - b).abs() <= 3e-7 * a.abs().max(b.abs()).max(1e-30),
        "{what}: {a} against {b}"
    );
}

fn cell(v: &Vtp, name: &str) -> Vec<f64> {
    v.cell(name)
        .unwrap_or_else(|| panic!("no cell array {name}"))
        .to_f64()
}

/// Check every frame of the series in `out` (`n` bodies of test case 1's
/// fibre, a frame every `every` steps of `dt`) against `trajectory.csv`
/// and the closed forms; the frames' files must say `compressed` or not.
fn check_series(
    out: &Path,
    n: usize,
    every: u64,
    dt: f64,
    compressed: bool,
) -> Vec<(f64, PathBuf)> {
    let traj = trajectory(out);
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let width = summary["steps_planned"].as_u64().unwrap().to_string().len();
    // The collection: valid XML, one DataSet per frame.
    let pvd_text = std::fs::read_to_string(out.join("fibres.pvd")).unwrap();
    let doc = roxmltree::Document::parse(&pvd_text).unwrap();
    let sets = doc
        .descendants()
        .filter(|x| x.has_tag_name("DataSet"))
        .count();
    let frames = read_pvd(&out.join("fibres.pvd")).unwrap();
    assert_eq!(sets, frames.len());
    // Fibre of test case 1 (docs/physics.md §6): D, L, ρ.
    let (d, l, rho) = (0.01f64, 0.025f64, 1100.0f64);
    let m = rho * std::f64::consts::PI * d * d * l / 4.0;
    let inertia = [
        m * d * d / 8.0,
        m * (3.0 * d * d / 4.0 + l * l) / 12.0,
        m * (3.0 * d * d / 4.0 + l * l) / 12.0,
    ];
    for (k, (t, file)) in frames.iter().enumerate() {
        let step = every * k as u64;
        assert_eq!(*t, step as f64 * dt, "frame {k}'s time is step·dt");
        // Zero-padded to the digits of the run's last step, so names sort.
        assert_eq!(file, &out.join(format!("vtk/fibres_{step:0width$}.vtp")));
        assert_eq!(xml_head(file), compressed, "{}", file.display());
        let v = read_vtp(file).unwrap();
        assert_eq!((v.n_lines, v.n_points), (n, 2 * n));
        assert_eq!(v.field("TimeValue").unwrap().to_f64(), vec![*t]);
        assert_eq!(v.field("step").unwrap().to_f64(), vec![step as f64]);
        let names: Vec<&str> = v.cells.iter().map(|a| a.name.as_str()).collect();
        let want: Vec<&str> = fibresim::output::vtk::CELL_ARRAYS
            .iter()
            .map(|c| c.0)
            .collect();
        assert_eq!(names, want);
        for (a, (_, comps, _)) in v.cells.iter().zip(fibresim::output::vtk::CELL_ARRAYS) {
            assert_eq!((a.components, a.tuples()), (comps, n), "{}", a.name);
        }
        assert_eq!(
            v.cell("quaternion").unwrap().component_names,
            ["w", "x", "y", "z"]
        );
        assert_eq!(
            v.lines[0].to_f64(),
            (0..2 * n as u32).map(f64::from).collect::<Vec<_>>(),
            "connectivity"
        );
        assert_eq!(
            v.lines[1].to_f64(),
            (1..=n).map(|k| 2.0 * k as f64).collect::<Vec<_>>(),
            "offsets"
        );
        let pts = v.points.to_f64();
        let (q4, ax, vel) = (
            cell(&v, "quaternion"),
            cell(&v, "axis"),
            cell(&v, "velocity"),
        );
        let (om, omb) = (cell(&v, "omega"), cell(&v, "omega_body"));
        let (speed, ke) = (cell(&v, "speed"), cell(&v, "kinetic_energy"));
        assert_eq!(
            cell(&v, "id"),
            (0..n as u32).map(f64::from).collect::<Vec<_>>()
        );
        assert_eq!(cell(&v, "material"), vec![0.0; n]);
        assert_eq!(cell(&v, "diameter"), vec![d as f32 as f64; n]);
        assert_eq!(cell(&v, "length"), vec![l as f32 as f64; n]);
        for b in 0..n {
            let s = &traj[&(step, b as u64)];
            let (x, q, vv, w) = (
                [s[0], s[1], s[2]],
                [s[3], s[4], s[5], s[6]],
                [s[7], s[8], s[9]],
                [s[10], s[11], s[12]],
            );
            // The stored Float32 is the rounding of the exact state.
            for c in 0..4 {
                assert_eq!(q4[4 * b + c], q[c] as f32 as f64, "q[{c}] of body {b}");
            }
            for c in 0..3 {
                assert_eq!(vel[3 * b + c], vv[c] as f32 as f64, "v[{c}] of body {b}");
                assert_eq!(om[3 * b + c], w[c] as f32 as f64, "omega[{c}] of body {b}");
            }
            let a = rot_x(q);
            let wb = to_body(q, w);
            for c in 0..3 {
                close32(ax[3 * b + c], a[c], "axis");
                close32(pts[6 * b + c], x[c] - 0.5 * l * a[c], "first end point");
                close32(
                    pts[6 * b + 3 + c],
                    x[c] + 0.5 * l * a[c],
                    "second end point",
                );
                assert!(
                    (omb[3 * b + c] - wb[c]).abs() <= 1e-6 * (1.0 + wb[c].abs()),
                    "omega_body"
                );
            }
            let v2: f64 = vv.iter().map(|c| c * c).sum();
            close32(speed[b], v2.sqrt(), "speed");
            let rot: f64 = (0..3).map(|c| 0.5 * inertia[c] * wb[c] * wb[c]).sum();
            close32(ke[b], 0.5 * m * v2 + rot, "kinetic energy");
        }
    }
    frames
}

#[test]
fn every_frame_reads_back_with_its_fields_values_and_time() {
    let dir = tempfile::tempdir().unwrap();
    let out = nine(dir.path(), &[]);
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    // Nine fibres: below 32 KiB of data, uncompressed.
    let frames = check_series(&out, 9, 40000, 1e-7, false);
    assert_eq!(frames.len(), 6, "steps 0, 40000, ..., 200000");
    // The last frame is the summary's final state.
    let last = read_vtp(&frames.last().unwrap().1).unwrap();
    let f0 = &summary["final"][0];
    let x: Vec<f64> = f0["x"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    let pts = last.points.to_f64();
    for c in 0..3 {
        close32(0.5 * (pts[c] + pts[3 + c]), x[c], "centre of body 0");
    }
    // The box outline: 8 corners, 12 edges of [0, 1]³.
    let b = read_vtp(&out.join("box.vtp")).unwrap();
    assert_eq!((b.n_points, b.n_lines), (8, 12));
    let corners = b.points.to_f64();
    assert!(corners.iter().all(|&c| c == 0.0 || c == 1.0));
    let ends = b.lines[0].to_f64();
    for e in ends.chunks(2) {
        let (p, q) = (e[0] as usize, e[1] as usize);
        let differ = (0..3)
            .filter(|&k| corners[3 * p + k] != corners[3 * q + k])
            .count();
        assert_eq!(differ, 1, "an edge joins corners that differ on one axis");
    }
}

/// 343 fibres (a 7³ lattice of tilted, moving, spinning fibres in a box):
/// over 32 KiB of data, so zlib-compressed frames, read back the same way.
#[test]
fn compressed_frames_of_a_lattice_read_back() {
    let mut text = String::from(
        "[simulation]\ndt = 1e-6\nt_end = 2e-5\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [0.28, 0.28, 0.28]\nyoung = 5e7\npoisson = 0.23\n[material.f]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n",
    );
    for k in 0..343 {
        let (i, j, l) = (k % 7, (k / 7) % 7, k / 49);
        let c = |g: usize| 0.02 + 0.04 * g as f64;
        let w = k as f64 * 0.37;
        text += &format!(
            "[[body]]\nshape = \"fibre\"\nmaterial = \"f\"\ndiameter = 0.01\nlength = 0.025\nposition = [{}, {}, {}]\naxis = [{}, {}, 1.0]\nvelocity = [{}, {}, 0.5]\nangular_velocity = [{}, 3.0, {}]\n",
            c(i), c(j), c(l), w.cos(), w.sin(), 0.3 * w.sin(), -0.2, 40.0 * w.cos(), 10.0 * w.sin()
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("lattice.toml");
    std::fs::write(&p, text).unwrap();
    let out = dir.path().join("o");
    ok(fibresim(&[
        "run",
        p.to_str().unwrap(),
        "--vtk-every",
        "5",
        "--trajectory-every",
        "5",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert_eq!(check_series(&out, 343, 5, 1e-6, true).len(), 5);
}

/// Contact counts: each frame's per-fibre counts against an independent
/// O(N²) scan (every pair and every wall through the kernels, no broad
/// phase), and their sum against energy.csv's touching pairs.
#[test]
fn contact_counts_match_a_brute_force_scan_and_energy_csv() {
    use fibresim::contact::{box_walls, contacts, Collider, FibreGeom, KernelCounters};
    // Two fibres dropped onto the floor, one on the other: contacts within 0.05 s.
    let text = r#"
[simulation]
dt = 1e-6
t_end = 0.06
[world]
gravity = [0.0, 0.0, -9.81]
[box]
min = [0.0, 0.0, 0.0]
max = [0.2, 0.2, 0.2]
young = 5e7
poisson = 0.23
[material.f]
density = 1100.0
young = 5e7
poisson = 0.35
[[body]]
shape = "fibre"
material = "f"
diameter = 0.01
length = 0.025
position = [0.1, 0.1, 0.006]
axis = [1.0, 0.0, 0.0]
[[body]]
shape = "fibre"
material = "f"
diameter = 0.01
length = 0.025
position = [0.1, 0.1, 0.02]
axis = [0.0, 1.0, 0.0]
[output]
vtk_every = 2000
trajectory_every = 2000
"#;
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("drop.toml");
    std::fs::write(&scene_path, text).unwrap();
    let out = dir.path().join("o");
    ok(fibresim(&[
        "run",
        scene_path.to_str().unwrap(),
        "--every",
        "2000",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]));
    let scene = common::scene_str(text);
    let traj = trajectory(&out);
    let mut energy = csv::Reader::from_path(out.join("energy.csv")).unwrap();
    let touching: Vec<f64> = energy
        .records()
        .map(|r| r.unwrap()[11].parse().unwrap())
        .collect();
    let walls = box_walls(scene.walls.as_ref().unwrap());
    let mut saw = [false; 2];
    for (k, (_, file)) in read_pvd(&out.join("fibres.pvd"))
        .unwrap()
        .iter()
        .enumerate()
    {
        let step = 2000 * k as u64;
        let v = read_vtp(file).unwrap();
        let counts = cell(&v, "contacts");
        let geom = |b: u64| {
            let s = &traj[&(step, b)];
            FibreGeom {
                centre: glam::DVec3::new(s[0], s[1], s[2]),
                axis: glam::DVec3::from_array(rot_x([s[3], s[4], s[5], s[6]])),
                radius: 0.005,
                half_length: 0.0125,
            }
        };
        let touch = |a: Collider, b: Collider| {
            let mut p = vec![];
            contacts(a, b, &mut p, &mut KernelCounters::default());
            !p.is_empty()
        };
        let (g0, g1) = (geom(0), geom(1));
        let pair = touch(Collider::Fibre(g0), Collider::Fibre(g1)) as u32;
        let on_walls = |g: &FibreGeom| {
            walls
                .iter()
                .filter(|w| touch(Collider::Fibre(*g), Collider::Wall(w)))
                .count() as u32
        };
        let want = [pair + on_walls(&g0), pair + on_walls(&g1)];
        assert_eq!(counts, want.map(f64::from), "step {step}");
        assert_eq!(
            touching[k],
            (pair + on_walls(&g0) + on_walls(&g1)) as f64,
            "energy.csv at step {step}"
        );
        saw[0] |= pair == 1;
        saw[1] |= on_walls(&g0) > 0;
    }
    assert_eq!(
        saw,
        [true, true],
        "the scene makes fibre-fibre and wall contacts"
    );
}

/// A run of 2T and a run of T resumed to 2T write the same VTK bytes, also
/// into another folder (the frames live in the `vtk/` subfolder).
#[test]
fn a_resumed_run_writes_the_same_vtk_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let whole = nine(dir.path(), &[]);
    let split = dir.path().join("split");
    ok(fibresim(&[
        "run",
        "scenarios/nine_fibres.toml",
        "--t-end",
        "0.01",
        "--vtk-every",
        "40000",
        "--trajectory-every",
        "40000",
        "--every",
        "20000",
        "--checkpoint-every",
        "60000",
        "-q",
        "--out",
        split.to_str().unwrap(),
    ]));
    let moved = dir.path().join("moved");
    let ckpt = split.join("checkpoint.json");
    resume_to(&ckpt, "0.02", &["--out", moved.to_str().unwrap()]);
    resume_to(&ckpt, "0.02", &[]);
    let mut files = vec![
        "fibres.pvd".to_string(),
        "box.vtp".into(),
        "trajectory.csv".into(),
        "energy.csv".into(),
    ];
    files.extend((0..=5).map(|k| format!("vtk/fibres_{:06}.vtp", 40000 * k)));
    for f in &files {
        let w = std::fs::read(whole.join(f)).unwrap();
        assert_eq!(
            w,
            std::fs::read(split.join(f)).unwrap(),
            "{f} (resumed in place)"
        );
        assert_eq!(
            w,
            std::fs::read(moved.join(f)).unwrap(),
            "{f} (resumed into another folder)"
        );
    }
}

#[test]
fn no_output_flag_writes_no_vtk_nor_trajectory() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    ok(fibresim(&[
        "run",
        "scenarios/nine_fibres.toml",
        "--t-end",
        "0.001",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]));
    for f in ["fibres.pvd", "box.vtp", "vtk", "trajectory.csv"] {
        assert!(!out.join(f).exists(), "{f} written without being asked for");
    }
}

#[test]
fn a_zero_cadence_is_bad_input_naming_its_key_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/torque_fibre.toml"
    ))
    .unwrap();
    let p = dir.path().join("s.toml");
    std::fs::write(&p, format!("{text}\n[output]\nvtk_every = 0\n")).unwrap();
    let o = fibresim(&[
        "run",
        p.to_str().unwrap(),
        "-q",
        "--out",
        dir.path().join("o").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    let line = text.lines().count() + 3;
    assert!(
        err.contains(&format!("s.toml:{line}:")) && err.contains("output.vtk_every: must be >= 1"),
        "{err}"
    );
    let o = fibresim(&[
        "run",
        "scenarios/torque_fibre.toml",
        "--trajectory-every",
        "0",
        "-q",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--trajectory-every: must be >= 1"));
}

/// VTK itself reads the series (`scripts/check_vtk.py`), when the `vtk`
/// package is importable; `.ci/run` installs it and runs the script.
#[test]
fn the_vtk_library_reads_the_series() {
    let dir = tempfile::tempdir().unwrap();
    let out = nine(dir.path(), &[]);
    let o = std::process::Command::new("python3")
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/check_vtk.py"))
        .arg(&out)
        .arg("--no-install")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output();
    let Ok(o) = o else {
        eprintln!("skipped: no python3");
        return;
    };
    if o.status.code() == Some(77) {
        eprintln!("skipped: {}", String::from_utf8_lossy(&o.stdout));
        return;
    }
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A dense scene of 384 fibres in live contact, above the parallel
/// threshold (compressed frames, forces on the pool): one thread, two
/// threads, and two threads split by a checkpoint and resumed write the same
/// VTK and trajectory bytes, and the frames carry contacts.
#[test]
fn a_dense_scene_writes_the_same_vtk_bytes_whatever_the_threads_and_resume() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("packed.toml");
    std::fs::write(&scene, common::packed_scene(6, 8, 8, 6e-4)).unwrap();
    let scene = scene.to_str().unwrap();
    let run = |out: &Path, extra: &[&str]| {
        let mut a = vec![
            "run",
            scene,
            "--out",
            out.to_str().unwrap(),
            "-q",
            "--every",
            "50",
        ];
        a.extend(extra);
        ok(fibresim(&a));
    };
    let (one, two, split) = (
        dir.path().join("one"),
        dir.path().join("two"),
        dir.path().join("split"),
    );
    let cadence = ["--vtk-every", "200", "--trajectory-every", "200"];
    run(&one, &[&cadence[..], &["--threads", "1"]].concat());
    run(&two, &[&cadence[..], &["--threads", "2"]].concat());
    run(
        &split,
        &[
            &cadence[..],
            &[
                "--threads",
                "2",
                "--t-end",
                "3e-4",
                "--checkpoint-every",
                "300",
            ],
        ]
        .concat(),
    );
    let ckpt = split.join("checkpoint.json");
    resume_to(&ckpt, "6e-4", &["--threads", "2"]);
    let mut files = vec![
        "fibres.pvd".to_string(),
        "box.vtp".into(),
        "trajectory.csv".into(),
    ];
    files.extend([0, 200, 400, 600].map(|s| format!("vtk/fibres_{s:03}.vtp")));
    for f in &files {
        let w = std::fs::read(one.join(f)).unwrap();
        assert_eq!(
            w,
            std::fs::read(two.join(f)).unwrap(),
            "{f}: 1 vs 2 threads"
        );
        assert_eq!(w, std::fs::read(split.join(f)).unwrap(), "{f}: resumed");
    }
    let last = read_vtp(&one.join("vtk/fibres_600.vtp")).unwrap();
    assert_eq!(last.n_lines, 384);
    let touching: f64 = cell(&last, "contacts").iter().sum();
    assert!(touching > 0.0, "the packed scene has live contacts");
}

/// A sphere in a frame (docs/guide.md): a zero-length line at its centre
/// (both points the trajectory's centre, rounded to f32), `length` 0, its
/// diameter, and its live contact counted on it and on the fibre it hits.
#[test]
fn a_sphere_is_a_zero_length_line_at_its_centre() {
    let dir = tempfile::tempdir().unwrap();
    // A sphere (D = 8 mm) 10 µm above a fibre's side at 0.5 m/s, no
    // gravity: they touch from step 20 for ~2e-4 s.
    let text = "[simulation]\ndt = 1e-6\nt_end = 3e-4\n[box]\nmin = [-0.1, -0.1, 0.0]\nmax = [0.1, 0.1, 0.1]\nyoung = 5e7\npoisson = 0.23\n[material.f]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n[[body]]\nshape = \"fibre\"\nmaterial = \"f\"\ndiameter = 0.01\nlength = 0.025\nposition = [0.0, 0.0, 0.02]\naxis = [1.0, 0.0, 0.0]\n[[body]]\nshape = \"sphere\"\nmaterial = \"f\"\ndiameter = 0.008\nposition = [0.002, 0.0, 0.02901]\nvelocity = [0.0, 0.0, -0.5]\n";
    let scene = dir.path().join("s.toml");
    std::fs::write(&scene, text).unwrap();
    let out = dir.path().join("o");
    ok(fibresim(&[
        "run",
        scene.to_str().unwrap(),
        "--vtk-every",
        "100",
        "--trajectory-every",
        "100",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]));
    let traj = trajectory(&out);
    let frame = read_vtp(&out.join("vtk").join("fibres_100.vtp")).unwrap();
    assert_eq!(cell(&frame, "length"), vec![0.025f32 as f64, 0.0]);
    assert_eq!(
        cell(&frame, "diameter"),
        vec![0.01f32 as f64, 0.008f32 as f64]
    );
    assert_eq!(
        cell(&frame, "contacts"),
        vec![1.0, 1.0],
        "touching at step 100"
    );
    let p = frame.points.to_f64();
    let centre = &traj[&(100, 1)][..3];
    for end in [&p[6..9], &p[9..12]] {
        for k in 0..3 {
            assert_eq!(
                end[k], centre[k] as f32 as f64,
                "sphere end {end:?}, centre {centre:?}"
            );
        }
    }
}
