//! What the loader and the run say about bad input, through the CLI: every
//! problem of a file in one report, each at its `file:line:column` with the
//! closest known name; TOML syntax errors in the same style; numbers
//! printed short; the unit hint wherever a size is implausible; a body
//! file's problems at the body file's line; the inertia check of a rigid
//! body with the tolerance of rounding. Each case exits 2 (3 for a guard)
//! without a panic.

use crate::common::fibresim;
use std::path::Path;
use std::process::Output;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `check FILE` on `text` written as `scene.toml` in a fresh folder, run
/// from that folder so the messages name `scene.toml`; its exit code and
/// stderr.
fn check_in(dir: &Path, text: &str) -> (Option<i32>, String) {
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_fibresim"))
        .args(["check", "scene.toml"])
        .current_dir(dir)
        .output()
        .expect("binary runs");
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "{err}");
    (o.status.code(), err)
}

fn check(text: &str) -> (Option<i32>, String) {
    let dir = tempfile::tempdir().unwrap();
    check_in(dir.path(), text)
}

/// Every needle in `err`.
fn has_all(err: &str, needles: &[&str]) {
    for n in needles {
        assert!(err.contains(n), "lacks `{n}`:\n{err}");
    }
}

const SIM: &str = "[simulation]\ndt = 1e-6\nt_end = 1e-3\n";
const BOX: &str =
    "[box]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nyoung = 5e7\npoisson = 0.23\n";
const FIBRE: &str = "[[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.025\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [0.5, 0.5, 0.5]\n";

/// Unknown tables and keys in every table, and names an enumerated key does
/// not take, all in one file: one report names each at its line and
/// column, with the closest known name, in file order.
#[test]
fn every_loader_problem_is_in_one_report() {
    let text = "\
[simulation]
dt = 1e-6
t_end = 1e-3
rotator = \"pcdmm\"
evry = 10

[wrld]
gravity = [0.0, 0.0, -9.81]

[box]
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
young = 5e7
poison = 0.23

[material.glass]
densty = 2500.0
young = 6e10
poisson = 0.2

[[body]]
shape = \"fiber\"
diameter = 0.01
length = 0.025
material = \"glas\"
position = [0.5, 0.5, 0.5]
colour = \"red\"

[output]
vtk_evry = 100

[contact]
restitutoin = 0.5

[guards]
overlap = 0.1
";
    let (code, err) = check(text);
    assert_eq!(code, Some(2), "{err}");
    let needles = [
        "11 problems; fix them all",
        "scene.toml:4:1: simulation.rotator: unknown rotator `pcdmm`; did you mean `pcdm`?",
        "scene.toml:5:1: simulation.evry: unknown key `evry`; did you mean `every`",
        "scene.toml:7:2: wrld: unknown table [wrld]; did you mean [world]",
        "scene.toml:14:1: box.poison: unknown key `poison`; did you mean `poisson`",
        "scene.toml:17:1: material.glass.densty: unknown key `densty`; did you mean `density`",
        "scene.toml:22:1: body[0].shape: unknown shape `fiber`; did you mean `fibre`?",
        "scene.toml:25:1: body[0].material: unknown material `glas`; did you mean `glass`?",
        "scene.toml:27:1: body[0].colour: unknown key `colour`; the keys of [[body]] are name, shape,",
        "scene.toml:30:1: output.vtk_evry: unknown key `vtk_evry`; did you mean `vtk_every`",
        "scene.toml:33:1: contact.restitutoin: unknown key `restitutoin`; did you mean `restitution`",
        "scene.toml:36:1: guards.overlap: unknown key `overlap`; did you mean `overlap_ratio`",
    ];
    has_all(&err, &needles);
    // One style: no raw parser or serde message, and in file order.
    assert!(
        !err.contains("TOML parse error") && !err.contains("unknown field"),
        "{err}"
    );
    let at: Vec<usize> = needles[1..].iter().map(|n| err.find(n).unwrap()).collect();
    assert!(
        at.windows(2).all(|w| w[0] < w[1]),
        "not in file order:\n{err}"
    );
    // The misspelt `poisson` is not also reported missing.
    assert!(!err.contains("box.poisson: missing"), "{err}");
}

/// A misspelt required table is named as such, not as a missing one; a key
/// outside any table is sent to the table it belongs in; a closed form
/// is an enumerated name like the others.
#[test]
fn misplaced_tables_and_keys_are_named_with_their_home() {
    let (code, err) = check(&format!(
        "{}\n{FIBRE}",
        SIM.replace("[simulation]", "[simulaton]")
    ));
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &["scene.toml:1:2: simulaton: unknown table [simulaton]; did you mean [simulation]"],
    );
    assert!(!err.contains("missing table"), "{err}");

    let (code, err) = check(&format!("gravity = [0.0, 0.0, -9.81]\n{SIM}\n{FIBRE}"));
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &["scene.toml:1:1: gravity: `gravity` is a key of [world], not a table of its own; write it under [world]"],
    );

    let body = "[[body]]\nshape = \"sphere\"\ndiameter = 2.0\ndensity = 1000.0\nposition = [0.0, 0.0, 0.0]\n";
    let (code, err) = check(&format!(
        "{SIM}\n{body}\n[reference]\nclosed_form = \"torque_free\"\n"
    ));
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &["reference.closed_form: unknown closed form `torque_free`; did you mean `torque-free`? choose one of exp-torque-sphere, torque-free, manufactured"],
    );
}

/// A file that is not TOML gets the parser's complaint in the same
/// `file:line:column: key: message` form as every other problem.
#[test]
fn syntax_errors_have_the_same_style() {
    let (code, err) = check("[simulation\ndt = 1e-6\n");
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &["error: scene.toml:1:12: TOML: invalid table header"],
    );
    assert!(
        !err.contains("TOML parse error") && !err.contains("  |"),
        "{err}"
    );
}

/// The numbers of a decimal string with more than 12 significant digits
/// (identifiers such as `rk4` are not numbers).
fn long_numbers(text: &str) -> Vec<String> {
    let b = text.as_bytes();
    let mut out = vec![];
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit() && (i == 0 || !b[i - 1].is_ascii_alphanumeric());
        if !starts {
            i += 1;
            continue;
        }
        let s = i;
        while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
            i += 1;
        }
        let mantissa = &text[s..i];
        let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
        let significant = digits.trim_start_matches('0').len();
        if significant > 12 {
            out.push(mantissa.to_string());
        }
    }
    out
}

/// Computed numbers in messages are printed to at most 12 significant
/// digits: the time of a guard stop (501 steps of 1e-6 s is 5.01e-4 s,
/// 5.009999999999999e-4 in shortest round-trip form), a start overlap
/// of crossed fibres (0.01 − 0.0025 = 0.0075 m, 0.0075000000000000535 in
/// floating point) and
/// the bounds of a tilted fibre (cos 30° terms).
#[test]
fn numbers_in_messages_are_short() {
    assert_eq!(
        long_numbers("t = 5.009999999999999e-4 s, rk4"),
        ["5.009999999999999"]
    );
    assert!(long_numbers("t = 5.01e-4 s, step 501").is_empty());

    // A fibre 0.39 mm above the floor at 1 m/s with a tight overlap guard
    // stops at step 501 (fixed by the geometry: 490 steps to the floor,
    // then 11 into it).
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "{SIM}\n{BOX}\n[guards]\noverlap_ratio = 0.001\n\n{}velocity = [0.0, 0.0, -1.0]\n",
        FIBRE.replace("[0.5, 0.5, 0.5]", "[0.5, 0.5, 0.00549]")
    );
    std::fs::write(dir.path().join("scene.toml"), text).unwrap();
    let scene = dir.path().join("scene.toml").display().to_string();
    let out = dir.path().join("o").display().to_string();
    let o = fibresim(&["run", &scene, "--out", &out, "-q", "--allow-large-dt"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{err}");
    has_all(
        &err,
        &["at step 501 (t = 5.01e-4 s)", "exceeds the limit 1e-3"],
    );
    assert!(long_numbers(&err).is_empty(), "{err}");

    // Two fibres 10 mm thick crossed at right angles, their axes 2.5 mm
    // apart: r1 + r2 − 2.5 mm = 7.5 mm of overlap.
    let second = FIBRE.replace(
        "[0.5, 0.5, 0.5]",
        "[0.5, 0.5, 0.5025]\naxis = [0.0, 1.0, 0.0]",
    );
    let (code, err) = check(&format!("{SIM}\n{BOX}\n{FIBRE}\n{second}"));
    assert_eq!(code, Some(2), "{err}");
    has_all(&err, &["overlaps body[1] `body1` by 0.0075 m at the start"]);
    assert!(long_numbers(&err).is_empty(), "{err}");

    // A fibre at 30° half through the floor.
    let tilted = FIBRE.replace(
        "position = [0.5, 0.5, 0.5]",
        "position = [0.2, 0.2, 0.0]\naxis = [0.8660254037844387, 0.0, 0.5]",
    );
    let (code, err) = check(&format!("{SIM}\n{BOX}\n{tilted}"));
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &["does not fit inside the box [0, 0, 0] .. [1, 1, 1]"],
    );
    assert!(long_numbers(&err).is_empty(), "{err}");
}

/// A fibre written in millimetres gets the unit hint when the first problem
/// found is that it does not fit inside the box, from a `[[body]]` table
/// and from a body file, and among the problems of a combined report.
#[test]
fn a_size_in_the_wrong_unit_gets_the_hint_wherever_it_fails() {
    let hint = "10 m is above the range of fibres, from nanofibres to 10 cm rods (1e-7 to 0.1 m); if you meant 10 mm or 10 µm or 10 cm, write 1e-2 or 1e-5 or 1e-1";
    let mm = FIBRE.replace("diameter = 0.01", "diameter = 10");
    let (code, err) = check(&format!("{SIM}\n{BOX}\n{mm}"));
    assert_eq!(code, Some(2), "{err}");
    has_all(&err, &["does not fit inside the box", hint]);
    assert_eq!(err.matches(hint).count(), 1, "said once:\n{err}");

    // With another problem in the file: the report, then the warning.
    let (code, err) = check(&format!(
        "{SIM}\n{BOX}\n{}",
        mm.replace("density", "densty")
    ));
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &[
            "body[0].densty: unknown key",
            "warning: scene.toml:13:1: body[0].diameter: 10 m is above",
        ],
    );

    // A body file in millimetres.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bed.csv"),
        "id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wbx,wby,wbz,diameter,length,material\n\
         0,0.5,0.5,0.5,1,0,0,0,0,0,0,0,0,0,10,25,pa\n",
    )
    .unwrap();
    let (code, err) = check_in(
        dir.path(),
        &format!("{SIM}\n{BOX}\n{MATERIAL}\n[bodies]\nfile = \"bed.csv\"\n"),
    );
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &[
            "bed.csv:2:2: x: body 0",
            "does not fit inside the box",
            hint,
        ],
    );
}

const MATERIAL: &str = "[material.pa]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n";

/// A body file with a header and no rows is named at its own header line,
/// not at the scenario's `[bodies]` line.
#[test]
fn a_header_only_body_file_is_named_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bed.csv"),
        "# no bodies yet\nid,x,y,z,qw,qx,qy,qz,vx,vy,vz,wbx,wby,wbz,diameter,length,material\n",
    )
    .unwrap();
    let (code, err) = check_in(
        dir.path(),
        &format!("{SIM}\n{BOX}\n{MATERIAL}\n[bodies]\nfile = \"bed.csv\"\n"),
    );
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &["error: bed.csv:2:1: header: the body file has no rows after its header"],
    );
}

/// `I1 + I2 = I3` (a lamina) is met to rounding and accepted;
/// a triple no body can have is refused, in the combined report too.
#[test]
fn inertia_is_checked_to_the_rounding_of_its_sum() {
    let rigid = |inertia: &str| {
        format!(
            "[simulation]\ndt = 1e-3\nt_end = 0.01\n\n[[body]]\nshape = \"rigid\"\nmass = 1.0\ninertia = {inertia}\nposition = [0.0, 0.0, 0.0]\nangular_velocity = [1.0, 0.1, 0.0]\n"
        )
    };
    // In binary each sum rounds below the third moment:
    // 2e-6 + 3e-6 = 4.999999999999999e-6, 0.3 + 0.6 = 0.8999999999999999.
    for lamina in [
        "[2e-6, 3e-6, 5e-6]",
        "[5e-6, 2e-6, 3e-6]",
        "[0.3, 0.9, 0.6]",
    ] {
        let (code, err) = check(&rigid(lamina));
        assert_eq!(code, Some(0), "{lamina}: {err}");
    }
    let (code, err) = check(&rigid("[1.0, 1.0, 2.000001]"));
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &["scene.toml:8:1: body[0].inertia: [1, 1, 2.000001] violates I1 + I2 >= I3"],
    );
    // With another problem: both in one report.
    let (code, err) = check(&rigid("[3.0, 1.0, 1.0]").replace("mass", "mas"));
    assert_eq!(code, Some(2), "{err}");
    has_all(
        &err,
        &[
            "2 problems",
            "body[0].mas: unknown key `mas`; did you mean `mass`",
            "body[0].inertia: [3, 1, 1] violates I2 + I3 >= I1",
        ],
    );
}
