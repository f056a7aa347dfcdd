//! The command line's habits: `-o/--out` on every command that writes (a
//! folder for runs and studies, a file for scenarios and pictures), the
//! picture format from the extension, folders created for written files,
//! and VTK frame names that sort by step.

use crate::common::{fibresim, ok, resume_to};
use std::path::Path;

/// Every command that writes takes `-o/--out`, with one meaning each.
#[test]
fn every_command_that_writes_takes_o_and_out() {
    for (cmd, value) in [
        ("run", "<DIR>"),
        ("settle", "<DIR>"),
        ("compare", "<DIR>"),
        ("converge", "<DIR>"),
        ("stress", "<DIR>"),
        ("generate", "<FILE>"),
        ("replicate", "<FILE>"),
        ("render", "<FILE>"),
        ("plot", "<FILE>"),
    ] {
        let help = ok(fibresim(&[cmd, "--help"]));
        assert!(
            help.contains(&format!("-o, --out {value}")),
            "`fibresim {cmd} --help` lacks `-o, --out {value}`:\n{help}"
        );
    }
}

/// `run -o DIR` writes its outputs there, as `--out DIR` does.
#[test]
fn run_takes_o_for_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("new").join("folder");
    ok(fibresim(&[
        "run",
        "scenarios/single_fibre.toml",
        "--t-end",
        "1e-4",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(out.join("energy.csv").is_file());
    assert!(out.join("summary.json").is_file());
}

fn starts_with(p: &Path, magic: &[u8]) -> bool {
    std::fs::read(p).unwrap().starts_with(magic)
}

const PNG: &[u8] = b"\x89PNG\r\n\x1a\n";

/// `render -o` writes the format its extension names (PNG or GIF), creates
/// the folder, and refuses any other extension (exit 2, naming the two it
/// writes) instead of writing PNG bytes under another name.
#[test]
fn render_writes_the_format_of_the_extension_or_refuses() {
    let dir = tempfile::tempdir().unwrap();
    let scene = "scenarios/nine_fibres.toml";
    let jpg = dir.path().join("x.jpg");
    let o = fibresim(&[
        "render",
        scene,
        "--size",
        "64x48",
        "-o",
        jpg.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("x.jpg") && err.contains("NAME.png") && err.contains("NAME.gif"),
        "{err}"
    );
    assert!(
        !jpg.exists(),
        "nothing written under a name of another format"
    );

    let png = dir.path().join("pictures").join("x.PNG");
    ok(fibresim(&[
        "render",
        scene,
        "--size",
        "64x48",
        "-o",
        png.to_str().unwrap(),
    ]));
    assert!(starts_with(&png, PNG));

    let gif = dir.path().join("x.gif");
    ok(fibresim(&[
        "render",
        scene,
        "--size",
        "64x48",
        "-o",
        gif.to_str().unwrap(),
    ]));
    assert!(
        starts_with(&gif, b"GIF89a"),
        "a .gif is a GIF without --gif"
    );

    let o = fibresim(&[
        "render",
        scene,
        "--gif",
        "--size",
        "64x48",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "--gif into a .png is refused");
    // The former long name still works.
    let old = dir.path().join("old.png");
    ok(fibresim(&[
        "render",
        scene,
        "--size",
        "64x48",
        "--output",
        old.to_str().unwrap(),
    ]));
    assert!(starts_with(&old, PNG));
}

/// `plot -o` refuses a format it does not write before any work, and
/// creates the folder of one it does.
#[test]
fn plot_refuses_an_unknown_format_and_creates_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("run");
    ok(fibresim(&[
        "run",
        "scenarios/single_fibre.toml",
        "--t-end",
        "1e-4",
        "-q",
        "--out",
        run.to_str().unwrap(),
    ]));
    let energy = run.join("energy.csv");
    let jpg = dir.path().join("fig").join("e.jpg");
    let o = fibresim(&[
        "plot",
        energy.to_str().unwrap(),
        "-o",
        jpg.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!dir.path().join("fig").exists(), "refused before any work");
    let svg = dir.path().join("fig").join("e.svg");
    ok(fibresim(&[
        "plot",
        energy.to_str().unwrap(),
        "-o",
        svg.to_str().unwrap(),
    ]));
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
}

/// `generate` and `replicate -o new_folder/bed.toml` create the folder, as
/// `run --out` does, and the written bed loads.
#[test]
fn generate_and_replicate_create_the_folder_of_their_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let bed = dir.path().join("beds").join("bed.toml");
    ok(fibresim(&[
        "generate",
        "--n",
        "4",
        "--diameter",
        "0.01",
        "--length",
        "0.03",
        "--box",
        "0.1,0.1,0.1",
        "-q",
        "-o",
        bed.to_str().unwrap(),
    ]));
    assert!(dir.path().join("beds/bed_bodies.csv").is_file());
    let big = dir.path().join("new_folder").join("big.toml");
    ok(fibresim(&[
        "replicate",
        bed.to_str().unwrap(),
        "--times",
        "2,1,1",
        "-q",
        "-o",
        big.to_str().unwrap(),
    ]));
    assert!(dir.path().join("new_folder/big_bodies.csv").is_file());
    let check = ok(fibresim(&["check", big.to_str().unwrap()]));
    assert!(check.contains(": 8 bodies"), "{check}");
}

/// The frame files of `fibres.pvd`, in its order, relative to `out`.
fn pvd_files(out: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(out.join("fibres.pvd")).unwrap();
    text.lines()
        .filter_map(|l| {
            l.split_once("file=\"")?
                .1
                .split_once('"')
                .map(|(f, _)| f.to_string())
        })
        .collect()
}

/// Sorted names of the frames in `out/vtk`.
fn frames_on_disk(out: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(out.join("vtk"))
        .unwrap()
        .map(|e| format!("vtk/{}", e.unwrap().file_name().to_string_lossy()))
        .collect();
    v.sort();
    v
}

/// Frame numbers are zero-padded to the digits of the run's last step, so
/// the names sort in time order (`fibres_01500` before `fibres_10000`); the
/// `.pvd` lists the same files in the same order. A run resumed to a later
/// end with more digits renames the frames written before and rewrites the
/// `.pvd`: it ends with the bytes of a run straight to that end.
#[test]
fn frame_names_sort_by_step_also_across_a_resume() {
    let dir = tempfile::tempdir().unwrap();
    let run = |out: &Path, t_end: &str, extra: &[&str]| {
        let mut a = vec![
            "run",
            "scenarios/single_fibre.toml",
            "--dt",
            "1e-6",
            "--t-end",
            t_end,
            "--vtk-every",
            "1500",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ];
        a.extend(extra);
        ok(fibresim(&a));
    };
    // 12 000 steps: frames 0, 1500, …, 12 000 (width 5).
    let straight = dir.path().join("straight");
    run(&straight, "0.012", &[]);
    let listed = pvd_files(&straight);
    assert_eq!(listed.len(), 9);
    assert_eq!(listed[1], "vtk/fibres_01500.vtp");
    assert_eq!(listed[7], "vtk/fibres_10500.vtp");
    assert_eq!(listed[8], "vtk/fibres_12000.vtp");
    assert_eq!(
        frames_on_disk(&straight),
        listed,
        "sorted names = time order"
    );

    // 6 000 steps (width 4: fibres_0000 … fibres_6000), resumed to 12 000.
    let split = dir.path().join("split");
    run(&split, "0.006", &["--checkpoint-every", "6000"]);
    assert_eq!(pvd_files(&split)[1], "vtk/fibres_1500.vtp");
    resume_to(&split.join("checkpoint.json"), "0.012", &[]);
    assert_eq!(frames_on_disk(&split), listed);
    for f in listed.iter().map(String::as_str).chain(["fibres.pvd"]) {
        assert_eq!(
            std::fs::read(straight.join(f)).unwrap(),
            std::fs::read(split.join(f)).unwrap(),
            "{f}: resumed against straight"
        );
    }
    // render reads the series through its .pvd.
    let png = dir.path().join("last.png");
    let said = ok(fibresim(&[
        "render",
        split.join("fibres.pvd").to_str().unwrap(),
        "--size",
        "64x48",
        "-o",
        png.to_str().unwrap(),
    ]));
    assert!(said.contains("step 12000"), "{said}");
}
