//! Body files, `fibresim generate` and the start-up overlap check, through
//! the CLI and the library: round trips to the bit, same seed same bytes,
//! what was asked for is what was placed, and bad rows named at file, line
//! and column with the fix.

use crate::common;
use common::fibresim;
use std::f64::consts::PI;
use std::path::Path;

fn ok(o: &std::process::Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn generate(dir: &Path, name: &str, extra: &[&str]) -> (String, String) {
    let toml = dir.join(format!("{name}.toml"));
    let mut args = vec![
        "generate",
        "--n",
        "300",
        "--length",
        "0.03",
        "--box",
        "0.2,0.2,0.2",
    ];
    args.extend(["-o", toml.to_str().unwrap()]);
    if !extra.contains(&"--diameter") {
        args.extend(["--diameter", "0.01"]);
    }
    args.extend_from_slice(extra);
    let out = ok(&fibresim(&args));
    (toml.display().to_string(), out)
}

/// A generated bed loads (so nothing overlaps: the check is exact, see
/// `contact::overlap_check`), written back from its loaded states it is
/// the same file byte for byte, and the same seed writes the same bytes.
#[test]
fn generated_beds_round_trip_and_repeat() {
    let dir = tempfile::tempdir().unwrap();
    let (a, report) = generate(
        dir.path(),
        "a",
        &["--seed", "5", "--speed", "0.5", "--spin", "20"],
    );
    let (b, _) = generate(
        dir.path(),
        "b",
        &["--seed", "5", "--speed", "0.5", "--spin", "20"],
    );
    let (c, _) = generate(
        dir.path(),
        "c",
        &["--seed", "6", "--speed", "0.5", "--spin", "20"],
    );
    let csv = |t: &str| std::fs::read(t.replace(".toml", "_bodies.csv")).unwrap();
    assert_eq!(csv(&a), csv(&b));
    assert_ne!(csv(&a), csv(&c));
    let scene = fibresim::scenario::load(Path::new(&a)).expect("a generated bed loads");
    assert_eq!(scene.bodies.len(), 300);
    let back = dir.path().join("back.csv");
    let names: Vec<String> = scene.materials.iter().map(|m| m.name.clone()).collect();
    fibresim::scenario::body_file::write(&back, &scene.ids, &scene.bodies, &scene.initial, &names)
        .unwrap();
    assert_eq!(std::fs::read(&back).unwrap(), csv(&a), "same bits back");
    // The reported volume fraction: Σ π D² L / 4 over the region (the box
    // less the gap D/20 on each side).
    let region = (0.2f64 - 2.0 * 0.0005).powi(3);
    let phi = 300.0 * PI * 0.01 * 0.01 * 0.03 / 4.0 / region;
    let printed: f64 = report.split("volume fraction ").nth(1).unwrap()[..6]
        .parse()
        .unwrap();
    assert!((printed - phi).abs() < 1e-4, "{report}: {phi}");
    assert!(report.contains("attempts"));
    // Speeds and spins as asked (spin normal to the axis).
    for s in &scene.initial {
        assert!((s.v.length() - 0.5).abs() < 1e-12);
        assert!((s.rot.omega_b.length() - 20.0).abs() < 1e-12 && s.rot.omega_b.x == 0.0);
    }
}

/// Ids other than the storage index (a body file numbered backwards) are
/// kept as given: the scene reports them, a body file written back holds
/// them, byte for byte, and a run's trajectory rows carry them. A file
/// numbered 0, 1, … in order keeps only the count (`Ids::Sequential`).
#[test]
fn ids_other_than_the_index_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    let (a, _) = generate(dir.path(), "a", &["--seed", "5", "--speed", "0.5"]);
    let csv_path = a.replace(".toml", "_bodies.csv");
    let text = std::fs::read_to_string(&csv_path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let rows = lines.len() - 1;
    for (k, line) in lines.iter_mut().skip(1).enumerate() {
        let rest = line.split_once(',').unwrap().1.to_string();
        *line = format!("{},{rest}", 1000 + rows - 1 - k);
    }
    let renumbered = lines.join("\n") + "\n";
    std::fs::write(&csv_path, &renumbered).unwrap();
    let scene = fibresim::scenario::load(Path::new(&a)).unwrap();
    assert!(matches!(scene.ids, fibresim::scenario::Ids::Listed(_)));
    assert_eq!(scene.ids.get(0), 1000 + rows as u64 - 1);
    assert_eq!(scene.name(rows - 1), "body1000");
    let back = dir.path().join("back.csv");
    let names: Vec<String> = scene.materials.iter().map(|m| m.name.clone()).collect();
    fibresim::scenario::body_file::write(&back, &scene.ids, &scene.bodies, &scene.initial, &names)
        .unwrap();
    assert_eq!(std::fs::read_to_string(&back).unwrap(), renumbered);
    let out = dir.path().join("run");
    ok(&fibresim(&[
        "run",
        &a,
        "--t-end",
        "2e-6",
        "--dt",
        "1e-6",
        "--trajectory-every",
        "1",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]));
    let traj = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let first_ids: Vec<&str> = traj
        .lines()
        .skip(1)
        .take(2)
        .map(|l| l.split(',').nth(2).unwrap())
        .collect();
    assert_eq!(
        first_ids,
        [
            format!("{}", 1000 + rows - 1),
            format!("{}", 1000 + rows - 2)
        ]
    );
}

/// Orientations: aligned fibres all point along the axis, planar ones lie
/// in the plane; distributed sizes stay within their bounds.
#[test]
fn orientations_and_size_distributions_are_as_asked() {
    let dir = tempfile::tempdir().unwrap();
    let (al, _) = generate(
        dir.path(),
        "al",
        &["--orientation", "aligned", "--axis", "1,1,0"],
    );
    let (pl, _) = generate(
        dir.path(),
        "pl",
        &[
            "--orientation",
            "planar",
            "--axis",
            "0,0,1",
            "--diameter",
            "uniform:0.005:0.01",
        ],
    );
    let axis = glam::DVec3::new(1.0, 1.0, 0.0).normalize();
    for s in &fibresim::scenario::load(Path::new(&al)).unwrap().initial {
        assert!((s.rot.q * glam::DVec3::X - axis).length() < 1e-12);
    }
    let p = fibresim::scenario::load(Path::new(&pl)).unwrap();
    for (s, b) in p.initial.iter().zip(&p.bodies) {
        assert!((s.rot.q * glam::DVec3::X).z.abs() < 1e-12);
        assert!((0.005..=0.01).contains(&b.shape.diameter()));
    }
    let o = fibresim(&[
        "generate",
        "--n",
        "100000",
        "--diameter",
        "0.01",
        "--length",
        "0.03",
        "--box",
        "0.1,0.1,0.1",
        "--max-attempts",
        "50",
        "-o",
        dir.path().join("x.toml").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("jammed at volume fraction"));
}

const HEAD: &str = "id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wbx,wby,wbz,diameter,length,material";
const ROW0: &str = "0,0.5,0.5,0.5,1.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.01,0.03,pa";
const ROW1: &str = "1,0.5,0.6,0.5,1.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.01,0.03,pa";

fn scene_with_rows(dir: &Path, rows: &[&str], extra: &str) -> String {
    let csv = dir.join("b.csv");
    std::fs::write(&csv, format!("{HEAD}\n# a comment\n{}\n", rows.join("\n"))).unwrap();
    let toml = dir.join("s.toml");
    std::fs::write(
        &toml,
        format!("[simulation]\ndt = 1e-6\nt_end = 1e-5\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nyoung = 5e7\npoisson = 0.3\n[material.pa]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n{extra}[bodies]\nfile = \"b.csv\"\n"),
    )
    .unwrap();
    toml.display().to_string()
}

/// Each bad row gets `file:line:column: column-name: what and the fix`,
/// exit 2 (the header is line 1, the comment line 2, so rows start at 3).
#[test]
fn bad_rows_name_file_line_column_and_fix() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("b.csv").display().to_string();
    let cases: Vec<(String, String)> = vec![
        (
            ROW1.replace("0.6", "x"),
            format!("{csv}:4:3: y: `x` is not a finite number"),
        ),
        (
            ROW1.replace(",pa", ""),
            format!("{csv}:4:17: material: the row has 16 columns"),
        ),
        (
            ROW1.replace(",pa", ",steel"),
            format!("{csv}:4:17: material: unknown material `steel`; define [material.steel]"),
        ),
        (
            ROW1.replace("1,0.5", "0,0.5"),
            format!("{csv}:4:1: id: id 0 appears twice"),
        ),
        (
            ROW1.replace("1.0,0.0,0.0,0.0,0.0", "1.1,0.0,0.0,0.0,0.0"),
            format!("{csv}:4:5: qw: qw,qx,qy,qz must be a unit quaternion"),
        ),
        (
            ROW1.replace("0.01,0.03", "-0.01,0.03"),
            format!("{csv}:4:15: diameter: must be > 0 m"),
        ),
        (
            ROW1.replace("0.6,0.5", "0.999,0.5"),
            format!("{csv}:4:2: x: body 1 (bounds"),
        ),
        (
            ROW1.replace("0.6,0.5", "0.505,0.5"),
            format!("{csv}:3:2: x: body 0 overlaps body 1 by"),
        ),
    ];
    for (row, want) in cases {
        let toml = scene_with_rows(dir.path(), &[ROW0, &row], "");
        let o = fibresim(&["check", &toml]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{row}: {err}");
        assert!(err.contains(&want), "{row}:\nwant {want}\ngot {err}");
        assert!(err.contains("; "), "a fix is given: {err}");
    }
    let toml = scene_with_rows(dir.path(), &[ROW0, ROW1], "");
    let text = std::fs::read_to_string(&toml)
        .unwrap()
        .replace("b.csv", "missing.csv");
    std::fs::write(&toml, text).unwrap();
    let err = String::from_utf8_lossy(&fibresim(&["check", &toml]).stderr).into_owned();
    assert!(
        err.contains("bodies.file: cannot read the body file") && err.contains(":14:1"),
        "{err}"
    );
}

/// A settled bed's resting contacts overlap a little: accepted up to
/// `guards.start_overlap_ratio` of the diameter, refused beyond.
#[test]
fn start_overlaps_are_accepted_up_to_the_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    // Side by side 9.99 mm apart: 10 µm overlap = 1e-3 D.
    let row = ROW1.replace("0.6,0.5", "0.50999,0.5");
    let tol = |r: &str| format!("[guards]\nstart_overlap_ratio = {r}\n");
    let o = fibresim(&[
        "check",
        &scene_with_rows(dir.path(), &[ROW0, &row], &tol("0.002")),
    ]);
    ok(&o);
    let o = fibresim(&[
        "check",
        &scene_with_rows(dir.path(), &[ROW0, &row], &tol("0.0005")),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        err.contains("more than guards.start_overlap_ratio = 5e-4"),
        "{err}"
    );
}

/// `fibresim replicate`: two parallel fibres, A pressed δ₁ into the box's
/// +x wall and B δ₂ into its −x wall, copied twice along x. The copies'
/// states are the source's bit for bit, moved by one box side; A of the
/// first copy and B of the second meet side by side at the seam with the
/// overlap δ₁ + δ₂ (2r minus their axis distance: closed form), so the bed
/// has 3 contacts (the two outer walls and the seam) where the copies had 2
/// each, and the written tolerance admits the seam.
#[test]
fn replicated_beds_copy_states_and_measure_the_seams() {
    let dir = tempfile::tempdir().unwrap();
    let (r, d1, d2) = (0.005, 1e-4, 1.95e-4);
    let (s, c) = (0.5f64.sqrt(), "0.05,0.05");
    let rows = format!(
        "id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wbx,wby,wbz,diameter,length,material\n\
         7,{},{c},{s},0.0,0.0,{s},0.1,-0.2,0.3,0.0,4.0,-5.0,0.01,0.03,pp\n\
         9,{},{c},{s},0.0,0.0,{s},0.0,0.0,0.0,1.5,0.0,0.0,0.01,0.03,pp\n",
        0.1 - r + d1,
        r - d2
    );
    std::fs::write(dir.path().join("two_bodies.csv"), rows).unwrap();
    let src = dir.path().join("two.toml");
    std::fs::write(
        &src,
        "[simulation]\ndt = 1e-6\nt_end = 1e-5\n\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [0.1, 0.1, 0.1]\n\
         young = 5e7\npoisson = 0.35\n\n[material.pp]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n\n\
         [guards]\nstart_overlap_ratio = 0.021\n\n[bodies]\nfile = \"two_bodies.csv\"\n",
    )
    .unwrap();
    let out = dir.path().join("big.toml");
    let report = ok(&fibresim(&[
        "replicate",
        src.to_str().unwrap(),
        "--times",
        "2,1,1",
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(
        report.contains("touching contacts 3 (the source: 2 each)"),
        "{report}"
    );
    let ratio = (d1 + d2) / (2.0 * r);
    assert!(
        report.contains(&format!("largest overlap ratio {ratio:.4}")),
        "{report}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("start_overlap_ratio = 0.03\n"), "{text}");
    let a = fibresim::scenario::load(&src).unwrap();
    let b = fibresim::scenario::load(&out).expect("the replicated bed loads");
    assert_eq!(b.ids, fibresim::scenario::Ids::Sequential(4));
    let w = b.walls.as_ref().unwrap();
    assert_eq!(
        (w.min.to_array(), w.max.to_array()),
        ([0.0; 3], [0.2, 0.1, 0.1])
    );
    // Each written body is one source body of one copy, bit for bit but
    // for the shift, and each (body, copy) is written once: numbered along
    // the space-filling curve, x first here, B0 (x = r − δ₂), A0, B1, A1.
    let mut written = vec![];
    for (t, body) in b.initial.iter().zip(b.bodies.iter()) {
        let (k, copy) = (0..2)
            .flat_map(|k| (0..2).map(move |c| (k, c)))
            .find(|&(k, c)| {
                let o = &a.initial[k];
                (t.v, t.rot.q, t.rot.omega_b) == (o.v, o.rot.q, o.rot.omega_b)
                    && t.x.to_array() == [o.x.x + 0.1 * c as f64, o.x.y, o.x.z]
            })
            .expect("a written body is a copy of a source body");
        assert_eq!(body, &a.bodies[k]);
        written.push((copy, k));
    }
    assert_eq!(written, [(0, 1), (0, 0), (1, 1), (1, 0)]);
    let bad = fibresim(&[
        "replicate",
        src.to_str().unwrap(),
        "--times",
        "2,0,1",
        "-o",
        "x.toml",
    ]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("NX,NY,NZ"));
}

/// `generate` writes the end time as given: 150 000 steps of 2e-5 s are
/// 3.0000000000000004 s in floating point, the user asked for 3.
#[test]
fn generate_writes_the_end_time_as_given() {
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = generate(dir.path(), "t", &["--dt", "2e-5", "--t-end", "3"]);
    let text = std::fs::read_to_string(&toml).unwrap();
    assert!(text.contains("\nt_end = 3.0\n"), "{text}");
}

/// A body file whose header ends in `shape` holds fibres and spheres (a
/// sphere's `length` empty); its bad rows are named like the others; a
/// file written back from the loaded scene is the same bytes, and a file
/// of fibres only keeps the 17 columns.
#[test]
fn a_shape_column_admits_spheres() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("b.csv");
    let toml = dir.path().join("s.toml");
    let head = format!("{HEAD},shape");
    let fibre = format!("{ROW0},fibre");
    let sphere = "1,0.5,0.6,0.5,1.0,0.0,0.0,0.0,0.0,0.0,-0.5,0.0,0.0,0.0,0.02,,pa,sphere";
    let write = |rows: &[&str]| {
        std::fs::write(&csv, format!("{head}\n{}\n", rows.join("\n"))).unwrap();
        std::fs::write(
            &toml,
            "[simulation]\ndt = 1e-6\nt_end = 1e-5\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nyoung = 5e7\npoisson = 0.3\n[material.pa]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n[bodies]\nfile = \"b.csv\"\n",
        )
        .unwrap();
    };
    write(&[&fibre, sphere]);
    let scene = fibresim::scenario::load(&toml).expect("a mixed body file loads");
    assert_eq!(
        scene.bodies[1].shape,
        fibresim::body::Shape::Sphere { diameter: 0.02 }
    );
    assert!(matches!(
        scene.bodies[0].shape,
        fibresim::body::Shape::Fibre { .. }
    ));
    let back = dir.path().join("back.csv");
    let names: Vec<String> = scene.materials.iter().map(|m| m.name.clone()).collect();
    fibresim::scenario::body_file::write(&back, &scene.ids, &scene.bodies, &scene.initial, &names)
        .unwrap();
    assert_eq!(
        std::fs::read_to_string(&back).unwrap(),
        std::fs::read_to_string(&csv).unwrap(),
        "same bytes back"
    );
    let fibres = dir.path().join("fibres.csv");
    let one = fibresim::body::Bodies::uniform(scene.bodies[0], 1);
    fibresim::scenario::body_file::write(
        &fibres,
        &fibresim::scenario::Ids::Sequential(1),
        &one,
        &scene.initial[..1],
        &names,
    )
    .unwrap();
    assert_eq!(
        std::fs::read_to_string(&fibres).unwrap(),
        format!("{HEAD}\n{ROW0}\n")
    );
    let file = csv.display().to_string();
    for (row, want) in [
        (
            sphere.replace(",,pa", ",0.03,pa"),
            format!("{file}:3:16: length: a sphere has no length, got `0.03`; leave the column empty"),
        ),
        (
            sphere.replace("sphere", "cube"),
            format!("{file}:3:18: shape: unknown shape `cube`; give fibre or sphere"),
        ),
        (
            sphere.replace(",pa,sphere", ",pa"),
            format!("{file}:3:18: shape: the row has 17 columns, the header 18; give a value for `shape`"),
        ),
        (
            fibre.replace("0.03,pa", ",pa"),
            format!("{file}:2:16: length: `` is not a finite number"),
        ),
    ] {
        let rows: Vec<&str> = if row.starts_with("0,") {
            vec![&row, sphere]
        } else {
            vec![&fibre, &row]
        };
        write(&rows);
        let o = fibresim(&["check", toml.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{row}: {err}");
        assert!(err.contains(&want), "{row}:\nwant {want}\ngot {err}");
    }
}

/// `generate --spheres N --sphere-diameter D` makes a bed of spheres or,
/// with `--n`, a mix: what was asked for is what was placed, nothing
/// overlaps (the bed loads: the start-up check is exact), the same seed
/// writes the same bytes, and a bed of fibres only is written as before
/// (17 columns).
#[test]
fn generate_makes_spheres_and_mixed_beds() {
    let dir = tempfile::tempdir().unwrap();
    let mixed = [
        "--spheres",
        "200",
        "--sphere-diameter",
        "uniform:0.01:0.02",
        "--seed",
        "3",
    ];
    let (a, report) = generate(dir.path(), "a", &mixed);
    let (b, _) = generate(dir.path(), "b", &mixed);
    let csv = |t: &str| std::fs::read(t.replace(".toml", "_bodies.csv")).unwrap();
    assert_eq!(csv(&a), csv(&b));
    assert!(
        report.contains("placed 300 fibres and 200 spheres"),
        "{report}"
    );
    let scene = fibresim::scenario::load(Path::new(&a)).expect("a mixed bed loads");
    let d: Vec<f64> = scene
        .bodies
        .iter()
        .filter_map(|b| match b.shape {
            fibresim::body::Shape::Sphere { diameter } => Some(diameter),
            _ => None,
        })
        .collect();
    assert_eq!((scene.bodies.len(), d.len()), (500, 200));
    assert!(d.iter().all(|&d| (0.01..=0.02).contains(&d)));
    // Only spheres: no fibre flags needed.
    let toml = dir.path().join("balls.toml");
    let out = ok(&fibresim(&[
        "generate",
        "--spheres",
        "100",
        "--sphere-diameter",
        "0.01",
        "--box",
        "0.1,0.1,0.1",
        "-o",
        toml.to_str().unwrap(),
    ]));
    assert!(out.contains("placed 100 spheres"), "{out}");
    let balls = fibresim::scenario::load(&toml).expect("a bed of spheres loads");
    assert_eq!(balls.bodies.len(), 100);
    let (f, _) = generate(dir.path(), "f", &[]);
    let text = String::from_utf8(csv(&f)).unwrap();
    assert!(text.starts_with(&format!("{HEAD}\n")), "{}", &text[..80]);
    // Asked for nothing, or spheres without their size: refused.
    for (args, want) in [
        (
            vec!["--box", "0.1,0.1,0.1"],
            "--n: give at least one fibre (--n) or sphere (--spheres)",
        ),
        (
            vec!["--spheres", "3", "--box", "0.1,0.1,0.1"],
            "--sphere-diameter: give --sphere-diameter for the spheres",
        ),
    ] {
        let toml = dir.path().join("x.toml");
        let o = fibresim(&[&["generate", "-o", toml.to_str().unwrap()], &args[..]].concat());
        assert_eq!(o.status.code(), Some(2));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(want), "{err}");
    }
}
