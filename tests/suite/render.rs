//! `fibresim render`: every input kind gives a PNG of the asked
//! size; the camera puts a fibre where the orthographic projection says and
//! as long as it is; the nearer of two crossing fibres is drawn on top; a
//! GIF has one frame per VTK frame; bad flags and inputs are exit 2.

use crate::common;
use common::{fibresim, ok};
use std::path::Path;

/// Decoded RGB pixels and the size.
fn png(p: &Path) -> (Vec<u8>, u32, u32) {
    let d = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(p).unwrap()));
    let mut r = d.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    buf.truncate(info.buffer_size());
    (buf, info.width, info.height)
}

fn px(img: &(Vec<u8>, u32, u32), x: u32, y: u32) -> [u8; 3] {
    let i = 3 * (y * img.1 + x) as usize;
    [img.0[i], img.0[i + 1], img.0[i + 2]]
}

fn white(c: [u8; 3]) -> bool {
    c.iter().all(|&v| v > 245)
}

/// Two fibres in the unit box: A along x at the centre (id 0), B along z in
/// front of it (smaller y, id 1), crossing it on screen in the front view.
const CROSS: &str = r#"
[simulation]
dt = 1e-6
t_end = 1e-5
[box]
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
young = 5e7
poisson = 0.23
[[body]]
shape = "fibre"
diameter = 0.05
length = 0.5
density = 1000.0
young = 5e7
poisson = 0.3
position = [0.5, 0.5, 0.5]
axis = [1.0, 0.0, 0.0]
[[body]]
shape = "fibre"
diameter = 0.05
length = 0.3
density = 1000.0
young = 5e7
poisson = 0.3
position = [0.5, 0.3, 0.5]
axis = [0.0, 0.0, 1.0]
"#;

#[test]
fn the_camera_places_and_sizes_a_fibre_and_draws_the_nearer_on_top() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("cross.toml");
    std::fs::write(&scene, CROSS).unwrap();
    let out = dir.path().join("front.png");
    ok(fibresim(&[
        "render",
        scene.to_str().unwrap(),
        "--view",
        "front",
        "--color",
        "id",
        "--range",
        "0,1",
        "--size",
        "800x600",
        "-o",
        out.to_str().unwrap(),
    ]));
    let img = png(&out);
    assert_eq!((img.1, img.2), (800, 600));
    // The drawing area (render::picture): x from 10, width 800 − 150 − 10; y
    // from 40, height 600 − 40 − 10; the unit box fitted at 95 %.
    let (aw, ah) = (640.0, 550.0);
    let scale = 0.95 * f64::min(aw, ah);
    let (cx, cy) = (10.0 + aw / 2.0, 40.0 + ah / 2.0);
    // Fibre A spans x = 0.25 … 0.75 on the row of the centre, 0.5 scale px long.
    // On its centre row, inside the box's edges (at cx ± scale/2), only the
    // fibres are drawn (B in the middle of A).
    let inside = (cx - 0.45 * scale) as u32..(cx + 0.45 * scale) as u32;
    let covered: Vec<u32> = inside.filter(|&x| !white(px(&img, x, cy as u32))).collect();
    let (first, last) = (covered[0], *covered.last().unwrap());
    let (want_first, want_last) = (cx - 0.25 * scale, cx + 0.25 * scale);
    assert!(
        (first as f64 - want_first).abs() <= 2.0 && (last as f64 - want_last).abs() <= 2.0,
        "fibre A drawn from {first} to {last}, expected {want_first:.1} to {want_last:.1}"
    );
    // Its width across: D = 0.05 → 0.05 scale px around the centre row.
    let col = (cx - 0.2 * scale) as u32;
    let rows: Vec<u32> = (45..590).filter(|&y| !white(px(&img, col, y))).collect();
    let height = rows
        .iter()
        .filter(|&&y| (y as f64 - cy).abs() < 0.1 * scale)
        .count() as f64;
    assert!(
        (height - 0.05 * scale).abs() <= 2.5,
        "fibre A is {height} px high, expected {:.1}",
        0.05 * scale
    );
    // At the crossing B (id 1: viridis' yellow end) is on top of A (purple):
    // red over blue there, blue over red on A alone.
    let on_b = px(&img, cx as u32, cy as u32);
    let on_a = px(&img, (cx - 0.2 * scale) as u32, cy as u32);
    assert!(on_b[0] > on_b[2], "the crossing shows B: {on_b:?}");
    assert!(on_a[2] > on_a[0], "A alone is purple: {on_a:?}");
    assert!(
        white(px(&img, 400, 580)) || px(&img, 400, 580)[0] > 60,
        "background"
    );
}

#[test]
fn every_input_kind_renders() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    ok(fibresim(&[
        "run",
        "scenarios/nine_fibres.toml",
        "--t-end",
        "0.002",
        "--vtk-every",
        "10000",
        "--trajectory-every",
        "10000",
        "--checkpoint-every",
        "20000",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]));
    let inputs = [
        "scenarios/nine_fibres.toml".to_string(),
        out.join("fibres.pvd").display().to_string(),
        out.join("vtk/fibres_10000.vtp").display().to_string(),
        out.join("trajectory.csv").display().to_string(),
        out.join("checkpoint.json").display().to_string(),
    ];
    for (k, input) in inputs.iter().enumerate() {
        let png_path = dir.path().join(format!("r{k}.png"));
        for color in ["speed", "angle_z", "contacts", "material", "none"] {
            let said = ok(fibresim(&[
                "render",
                input,
                "--color",
                color,
                "--size",
                "320x240",
                "-o",
                png_path.to_str().unwrap(),
            ]));
            assert!(said.contains("r"), "{said}");
            let img = png(&png_path);
            assert_eq!((img.1, img.2), (320, 240));
            assert!(
                img.0.iter().any(|&v| v < 200),
                "{input}: something is drawn"
            );
        }
    }
    // A still of a chosen step of the series, and an animation of all of it.
    let still = dir.path().join("s.png");
    let said = ok(fibresim(&[
        "render",
        &inputs[1],
        "--step",
        "10000",
        "-o",
        still.to_str().unwrap(),
    ]));
    assert!(said.contains("step 10000"), "{said}");
    let gif_path = dir.path().join("a.gif");
    let said = ok(fibresim(&[
        "render",
        &inputs[1],
        "--gif",
        "--size",
        "300x200",
        "-o",
        gif_path.to_str().unwrap(),
    ]));
    assert!(said.contains("3 frames"), "{said}");
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts
        .read_info(std::fs::File::open(&gif_path).unwrap())
        .unwrap();
    let mut n = 0;
    while let Some(f) = d.read_next_frame().unwrap() {
        assert_eq!((f.width, f.height), (300, 200));
        n += 1;
    }
    assert_eq!(n, 3, "steps 0, 10000, 20000");
    // The same from the trajectory.
    let said = ok(fibresim(&[
        "render",
        &inputs[3],
        "--gif",
        "--size",
        "300x200",
        "-o",
        gif_path.to_str().unwrap(),
    ]));
    assert!(said.contains("3 frames"), "{said}");
}

#[test]
fn bad_flags_and_inputs_are_exit_2_with_the_fix() {
    let cases: [(&[&str], &str); 6] = [
        (
            &["render", "scenarios/nine_fibres.toml", "--color", "colour"],
            "--color: unknown field `colour`; choose one of speed",
        ),
        (
            &["render", "scenarios/nine_fibres.toml", "--view", "1,2"],
            "--view: `1,2` is not three finite numbers",
        ),
        (
            &["render", "scenarios/nine_fibres.toml", "--size", "big"],
            "--size: `big` is not two numbers",
        ),
        (
            &["render", "scenarios/nine_fibres.toml", "--range", "2,1"],
            "--range: needs LO < HI",
        ),
        (&["render", "no/such.pvd"], "cannot read"),
        (&["render", "README.md"], "cannot tell what this is"),
    ];
    for (args, msg) in cases {
        let o = fibresim(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(msg), "{args:?}: {err}");
    }
    // A trajectory without its summary needs --scenario.
    let dir = tempfile::tempdir().unwrap();
    let t = dir.path().join("trajectory.csv");
    std::fs::write(&t, "step,t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n").unwrap();
    let o = fibresim(&["render", t.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--scenario PATH"));
}

/// A still is drawn in bands on the thread pool and a GIF's frames in
/// parallel: the bytes are the same on one thread and on two.
#[test]
fn pictures_are_the_same_bytes_whatever_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("packed.toml");
    std::fs::write(&scene, common::packed_scene(6, 8, 8, 2e-5)).unwrap();
    let out = dir.path().join("o");
    ok(fibresim(&[
        "run",
        scene.to_str().unwrap(),
        "--vtk-every",
        "10",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]));
    let pvd = out.join("fibres.pvd");
    let pvd = pvd.to_str().unwrap();
    let mut bytes = vec![];
    for threads in ["1", "2"] {
        let (png, gif) = (
            dir.path().join(format!("s{threads}.png")),
            dir.path().join(format!("a{threads}.gif")),
        );
        for (extra, path) in [(None, &png), (Some("--gif"), &gif)] {
            let mut a = vec!["--threads", threads, "render", pvd, "--size", "600x500"];
            a.extend(extra);
            a.extend(["-o", path.to_str().unwrap()]);
            ok(fibresim(&a));
        }
        bytes.push((std::fs::read(&png).unwrap(), std::fs::read(&gif).unwrap()));
    }
    assert!(
        bytes[0].0 == bytes[1].0,
        "the still differs between 1 and 2 threads"
    );
    assert!(
        bytes[0].1 == bytes[1].1,
        "the GIF differs between 1 and 2 threads"
    );
}
