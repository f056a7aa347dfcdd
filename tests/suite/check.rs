//! `fibresim check` and the `run` warning: every printed number against a
//! value computed here from its closed form (docs/physics.md §2, §3, §8), not from the
//! library's functions.

use crate::common;
use common::fibresim;

use std::f64::consts::PI;
use std::process::Output;

fn stdout(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The numbers after `label` in `line` (until the next letter other than e).
fn numbers_after(line: &str, label: &str) -> Vec<f64> {
    let rest = &line[line
        .find(label)
        .unwrap_or_else(|| panic!("{label}: {line}"))
        + label.len()..];
    // `x` ends a margin ("62.4x").
    rest.split(|c: char| ",()x".contains(c) || c.is_whitespace())
        .take_while(|w| w.is_empty() || w.parse::<f64>().is_ok())
        .filter(|w| !w.is_empty())
        .map(|w| w.parse().unwrap())
        .collect()
}

/// The cells of a row: split on runs of two or more spaces (the report's
/// documented separator).
fn cells(line: &str) -> Vec<String> {
    line.trim()
        .split("  ")
        .map(str::trim)
        .filter(|c| !c.is_empty())
        .map(str::to_string)
        .collect()
}

/// The table whose header row holds `column`: each row as (header, cell)
/// pairs, until the first line that is not a row of it.
fn table(text: &str, column: &str) -> Vec<Vec<(String, String)>> {
    let mut lines = text
        .lines()
        .skip_while(|l| !cells(l).iter().any(|c| c == column));
    let header = cells(
        lines
            .next()
            .unwrap_or_else(|| panic!("no table with `{column}`:\n{text}")),
    );
    lines
        .map(cells)
        .take_while(|c| c.len() == header.len())
        .map(|c| header.iter().cloned().zip(c).collect())
        .collect()
}

/// Cell `column` of `row` as a number.
fn num(row: &[(String, String)], column: &str) -> f64 {
    let c = &row
        .iter()
        .find(|(h, _)| h == column)
        .unwrap_or_else(|| panic!("{column}: {row:?}"))
        .1;
    c.parse().unwrap_or_else(|_| panic!("{column} = {c}"))
}

/// The row of `rows` whose first cell is `first`.
fn row<'a>(rows: &'a [Vec<(String, String)>], first: &str) -> &'a [(String, String)] {
    rows.iter()
        .find(|r| r[0].1 == first)
        .unwrap_or_else(|| panic!("no row `{first}` in {rows:?}"))
}

fn line_with<'a>(text: &'a str, needle: &str) -> &'a str {
    text.lines()
        .find(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("no line with `{needle}`:\n{text}"))
}

/// `x` printed with 5 significant digits equals `want`.
fn close(x: f64, want: f64, what: &str) {
    assert!(
        ((x - want) / want).abs() < 1e-4,
        "{what}: printed {x:e}, computed {want:e}"
    );
}

/// Hertz collision time constant `2 I (15/16)^{2/5}`, `I = ∫₀¹ (1 − x^{5/2})^{−1/2} dx`,
/// by Simpson's rule after `x = 1 − u²` (which removes the endpoint singularity).
fn hertz_constant() -> f64 {
    let f = |u: f64| {
        if u == 0.0 {
            2.0 / 2.5f64.sqrt()
        } else {
            2.0 * u / (1.0 - (1.0 - u * u).powf(2.5)).sqrt()
        }
    };
    let n = 2000;
    let h = 1.0 / n as f64;
    let s: f64 = (0..=n)
        .map(|k| {
            let w = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * f(k as f64 * h)
        })
        .sum();
    2.0 * (s * h / 3.0) * (15.0f64 / 16.0).powf(0.4)
}

/// Test case 1's fibre (scenarios/single_fibre.toml: D = 0.01, L = 0.025,
/// ρ = 1100, E = 5e7, ν = 0.35; walls E = 5e7, ν = 0.23; centre at 0.5 m).
struct Fibre {
    d: f64,
    l: f64,
    rho: f64,
    e: f64,
    nu: f64,
}

const TC1: Fibre = Fibre {
    d: 0.01,
    l: 0.025,
    rho: 1100.0,
    e: 5e7,
    nu: 0.35,
};

impl Fibre {
    fn mass(&self) -> f64 {
        self.rho * PI * self.d * self.d * self.l / 4.0
    }
    fn inertia(&self) -> (f64, f64) {
        let (m, r) = (self.mass(), self.d / 2.0);
        (
            m * self.d * self.d / 8.0,
            m * (3.0 * r * r + self.l * self.l) / 12.0,
        )
    }
    /// Effective mass at the worst contact: the side's end point along the
    /// side normal, lever arm L/2 (L > D), hand-derived: 1/m + (L/2)²/I_t.
    fn worst_effective_mass(&self) -> f64 {
        1.0 / (1.0 / self.mass() + (self.l / 2.0).powi(2) / self.inertia().1)
    }
    fn rayleigh(&self) -> f64 {
        let g = self.e / (2.0 * (1.0 + self.nu));
        PI * self.d / 2.0 * (self.rho / g).sqrt() / (0.1631 * self.nu + 0.8766)
    }
}

fn e_star(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

fn hertz_time(m: f64, r: f64, e: f64, v: f64) -> f64 {
    hertz_constant() * (m * m / (r * e * e * v)).powf(0.2)
}

/// Face-tilt period on a wall (src/advice.rs docs): peak Hertz force
/// `F = (4/3) E* √R* δ^{3/2}` with `δ = (15 m v² / (16 E* √R*))^{2/5}`, tilt
/// stiffness `F (4 r / s0 − L/2)`, `s0 = 0.0025` (fibre_wall::FACE_BLEND_SIN).
fn wall_tilt_period(f: &Fibre, m: f64, e: f64, v: f64) -> f64 {
    let r = f.d / 2.0;
    let depth = (15.0 * m * v * v / (16.0 * e * r.sqrt())).powf(0.4);
    let force = 4.0 / 3.0 * e * r.sqrt() * depth.powf(1.5);
    2.0 * PI * (f.inertia().1 / (force * (4.0 * r / 0.0025 - f.l / 2.0))).sqrt()
}

#[test]
fn hertz_constant_matches_the_beta_function() {
    // (2/5) B(2/5, 1/2) = 1.4716375921623523 (src/contact/hertz.rs; Γ values
    // from any table): the quadrature above is right to 1e-6.
    let want = 2.0 * 1.471_637_592_162_352_3 * (15.0f64 / 16.0).powf(0.4);
    assert!((hertz_constant() - want).abs() < 1e-6 * want);
}

#[test]
fn check_prints_mass_inertia_hertz_and_rayleigh_times() {
    let out = stdout(&fibresim(&["check", "scenarios/single_fibre.toml"]));
    let f = TC1;
    let (m, (ia, it)) = (f.mass(), f.inertia());
    assert!(
        out.starts_with(
            "scenario scenarios/single_fibre.toml: 1 body, dt = 1e-7 s, 20000000 steps (t_end = "
        ),
        "{out}"
    );
    let bodies = table(&out, "mass (kg)");
    let body = row(&bodies, "0");
    assert_eq!(body[1].1, "fibre", "name");
    assert_eq!((num(body, "D (m)"), num(body, "L (m)")), (f.d, f.l));
    close(num(body, "mass (kg)"), m, "mass");
    close(num(body, "I_x (kg m^2)"), ia, "I_axial");
    close(num(body, "I_y (kg m^2)"), it, "I_transverse");
    close(num(body, "I_z (kg m^2)"), it, "I_transverse");
    let materials = table(&out, "density (kg/m^3)");
    let mat = row(&materials, "fibre");
    assert_eq!(
        (
            num(mat, "density (kg/m^3)"),
            num(mat, "young (Pa)"),
            num(mat, "poisson (-)")
        ),
        (f.rho, f.e, f.nu)
    );

    // At rest 0.5 m above the floor: E = m g h, all of it into the worst contact.
    let energy = m * 9.81 * 0.5;
    close(numbers_after(&out, "E_avail = ")[0], energy, "E_avail");
    let m_eff = f.worst_effective_mass();
    // Hand value: L/2 = 0.0125, I_t/m = (3 · 0.005² + 0.025²)/12 = 5.8333e-5,
    // so m/m_eff = 1 + 1.5625e-4/5.8333e-5 = 3.6786.
    assert!((m / m_eff - 3.678_571).abs() < 1e-5);
    let v = (2.0 * energy / m_eff).sqrt();
    let t_h = hertz_time(m_eff, f.d / 2.0, e_star(f.e, f.nu, 5e7, 0.23), v);
    let t_r = f.rayleigh();
    let t_tilt = wall_tilt_period(&f, m_eff, e_star(f.e, f.nu, 5e7, 0.23), v);
    let pairs = table(&out, "t_Hertz (s)");
    let wall = row(&pairs, "fibre – wall");
    let [ms, mt, vmax, th, tt, tr] = [
        "m* (kg)",
        "m_trans (kg)",
        "v_max (m/s)",
        "t_Hertz (s)",
        "t_tilt (s)",
        "t_Rayleigh (s)",
    ]
    .map(|c| num(wall, c));
    close(ms, m_eff, "m*");
    close(mt, m, "m_trans");
    close(vmax, v, "v_max");
    close(th, t_h, "t_Hertz");
    close(tt, t_tilt, "t_tilt");
    close(tr, t_r, "t_Rayleigh");
    assert!(
        out.contains("max(D/2, L/2)"),
        "the output says how m* is bounded"
    );

    // The face tilt is the fastest motion here (1.2e-4 s against 3.1e-4 s).
    let rec = (t_h / 50.0).min(0.2 * t_r).min(t_tilt / 50.0);
    assert_eq!(rec, t_tilt / 50.0);
    let line = line_with(&out, "recommended dt <=");
    let printed = numbers_after(line, "recommended dt <= ")[0];
    assert!(
        (printed / rec - 1.0).abs() < 1e-3,
        "{line}; computed {rec:e}"
    );
    let margin = numbers_after(line, "margin ")[0];
    assert!((margin / (rec / 1e-7) - 1.0).abs() < 1e-3, "{line}");
}

/// A sphere (D = 0.01 m, 0.05 m above the floor) over a fibre lying on
/// it: the sphere–wall row has the Hertz time of the sphere itself (every
/// normal through its centre, m* = m, R* = D/2), the sphere–fibre row sums
/// 1/m of the sphere and 1/m_eff of the fibre at `1/R* = 2/D_s + 2/D_f`,
/// the Rayleigh time is the sphere's radius's, and a fibre's face rocking
/// on a sphere of radius 5 mm < L/2 has no tilt mode (inf).
#[test]
fn check_times_sphere_contacts() {
    let dir = tempfile::tempdir().unwrap();
    let text = "[simulation]\ndt = 1e-6\nt_end = 0.02\n[world]\ngravity = [0.0, 0.0, -9.81]\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [0.1, 0.1, 0.1]\nyoung = 5e7\npoisson = 0.23\n[material.m]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n[[body]]\nname = \"ball\"\nshape = \"sphere\"\nmaterial = \"m\"\ndiameter = 0.01\nposition = [0.05, 0.05, 0.05]\n[[body]]\nname = \"rod\"\nshape = \"fibre\"\nmaterial = \"m\"\ndiameter = 0.01\nlength = 0.025\nposition = [0.05, 0.05, 0.02]\naxis = [1.0, 0.0, 0.0]\n";
    let out = stdout(&fibresim(&["check", &write_scene(dir.path(), text)]));
    let f = TC1;
    let m_s = 1100.0 * PI * 0.01f64.powi(3) / 6.0;
    let v_s = (2.0 * 9.81 * 0.05f64).sqrt();
    let v_f = (2.0 * f.mass() * 9.81 * 0.02 / f.worst_effective_mass()).sqrt();
    let pairs = table(&out, "t_Hertz (s)");
    let t_r = {
        let g = 5e7 / (2.0 * (1.0 + 0.35));
        PI * 0.005 * (1100.0f64 / g).sqrt() / (0.1631 * 0.35 + 0.8766)
    };
    let wall = row(&pairs, "ball – wall");
    let e_wall = e_star(5e7, 0.35, 5e7, 0.23);
    close(num(wall, "m* (kg)"), m_s, "sphere m*");
    close(num(wall, "v_max (m/s)"), v_s, "sphere v_max");
    close(
        num(wall, "t_Hertz (s)"),
        hertz_time(m_s, 0.005, e_wall, v_s),
        "sphere–wall t_Hertz",
    );
    close(num(wall, "t_Rayleigh (s)"), t_r, "sphere t_Rayleigh");
    assert_eq!(wall[5].1, "inf", "a sphere has no tilt mode: {wall:?}");
    let pair = row(&pairs, "ball – rod");
    let m = 1.0 / (1.0 / m_s + 1.0 / f.worst_effective_mass());
    close(num(pair, "m* (kg)"), m, "sphere–fibre m*");
    close(
        num(pair, "t_Hertz (s)"),
        hertz_time(
            m,
            1.0 / (2.0 / 0.01 + 2.0 / 0.01),
            e_star(5e7, 0.35, 5e7, 0.35),
            v_s + v_f,
        ),
        "sphere–fibre t_Hertz",
    );
    assert_eq!(pair[5].1, "inf", "{pair:?}");
}

/// Nine fibres: a fibre–fibre pair sums both bodies' 1/m_eff and their
/// speed bounds, each bound from one body's own energy (the highest body's).
#[test]
fn check_pairs_sum_effective_masses_and_speeds() {
    let out = stdout(&fibresim(&["check", "scenarios/nine_fibres.toml"]));
    let f = TC1;
    let m = f.mass();
    // Nine bodies at v = (1, -1, 0) on the grid x, z ∈ {0.25, 0.5, 0.75}:
    // the top row brings the most, ½ m |v|² + m g 0.75.
    let energy = 0.5 * m * 2.0 + m * 9.81 * 0.75;
    close(numbers_after(&out, "E_avail = ")[0], energy, "E_avail");
    let m_eff = f.worst_effective_mass();
    let pairs = table(&out, "t_Hertz (s)");
    let pair = row(&pairs, "fibre0 – fibre0 (same kind)");
    close(num(pair, "m* (kg)"), m_eff / 2.0, "m* of a pair");
    close(num(pair, "m_trans (kg)"), m / 2.0, "m_trans of a pair");
    let v = 2.0 * (2.0 * energy / m_eff).sqrt();
    close(num(pair, "v_max (m/s)"), v, "v_max of a pair");
    let t_h = hertz_time(m_eff / 2.0, f.d / 4.0, e_star(f.e, f.nu, f.e, f.nu), v);
    close(num(pair, "t_Hertz (s)"), t_h, "t_Hertz of a pair");
    assert!(
        out.contains("scenarios/nine_fibres.toml: 9 bodies,"),
        "{out}"
    );
    assert_eq!(table(&out, "mass (kg)").len(), 9);
}

/// A brute-force search over the cylinder's surface points and their
/// normals (faces, side, and the rim's cone of normals) finds no contact with
/// a smaller effective mass than the advice uses, and reaches it.
#[test]
fn worst_effective_mass_is_the_minimum_over_the_surface() {
    use fibresim::advice::min_effective_mass;
    use fibresim::body::{Body, Shape};
    use glam::DVec3;
    for (d, l) in [(0.01, 0.025), (0.001, 0.1), (0.02, 0.005)] {
        let b = Body::new(
            Shape::Fibre {
                diameter: d,
                length: l,
            },
            0,
            1100.0,
        );
        let inv_i = b.inertia.inverse;
        let inv_m_eff = |r: DVec3, n: DVec3| 1.0 / b.mass + (r.cross(n) * r.cross(n)).dot(inv_i);
        let (r0, h) = (d / 2.0, l / 2.0);
        let mut worst: f64 = 0.0;
        let k = 40;
        for i in 0..=k {
            let phi = 2.0 * PI * i as f64 / k as f64;
            let radial = DVec3::new(0.0, phi.cos(), phi.sin());
            for j in 0..=k {
                let s = j as f64 / k as f64;
                // Side point at x, side normal; face point at radius s·r, face normal.
                let side = inv_m_eff(
                    DVec3::new(h * (2.0 * s - 1.0), 0.0, 0.0) + r0 * radial,
                    radial,
                );
                let face = inv_m_eff(DVec3::X * h + s * r0 * radial, DVec3::X);
                // Rim point with a normal of its cone, at angle α from the axis.
                let a = s * PI / 2.0;
                let rim = inv_m_eff(
                    DVec3::X * h + r0 * radial,
                    a.cos() * DVec3::X + a.sin() * radial,
                );
                worst = worst.max(side).max(face).max(rim);
            }
        }
        let (m_eff, arm) = min_effective_mass(&b);
        assert_eq!(arm, r0.max(h));
        assert!((1.0 / worst - m_eff).abs() < 1e-12 * m_eff, "D {d}, L {l}");
    }
}

fn write_scene(dir: &std::path::Path, text: &str) -> String {
    let p = dir.join("scene.toml");
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// `run` warns on stderr when dt is above the recommendation, and only then.
#[test]
fn run_warns_above_the_recommended_dt() {
    let dir = tempfile::tempdir().unwrap();
    let f = TC1;
    let m_eff = f.worst_effective_mass();
    let v = (2.0 * f.mass() * 9.81 * 0.5 / m_eff).sqrt();
    let t_h = hertz_time(m_eff, f.d / 2.0, e_star(f.e, f.nu, 5e7, 0.23), v);
    let t_tilt = wall_tilt_period(&f, m_eff, e_star(f.e, f.nu, 5e7, 0.23), v);
    let rec = (t_h / 50.0).min(0.2 * f.rayleigh()).min(t_tilt / 50.0);
    let scene = "scenarios/single_fibre.toml";
    for (dt, warns) in [(1e-5, true), (2e-6, false)] {
        assert_eq!(dt > rec, warns, "rec = {rec:e}");
        let out = dir.path().join(format!("{dt}"));
        let o = fibresim(&[
            "run",
            scene,
            "--dt",
            &format!("{dt:e}"),
            "--t-end",
            "1e-3",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        let want = format!("warning: dt = {dt:e} s is above the recommended ");
        assert_eq!(err.contains(&want), warns, "want `{want}`: {err}");
        assert_eq!(err.contains("warning"), warns, "{err}");
        if warns {
            let printed = numbers_after(&err, &want)[0];
            assert!(
                (printed / rec - 1.0).abs() < 1e-3,
                "{err}; computed {rec:e}"
            );
        }
    }
}

/// Speeds at or above light speed are bad input, not `recommended dt <= 0`.
#[test]
fn check_rejects_non_physical_speeds() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/single_fibre.toml"),
    )
    .unwrap();
    for (add, key) in [
        (
            "velocity = [0.0, 0.0, -1e300]\n",
            "body[0].velocity: speed 1e300 m/s is not physical",
        ),
        (
            "angular_velocity = [0.0, 3e10, 0.0]\n",
            "body[0].angular_velocity: rim speed",
        ),
    ] {
        let scene = write_scene(dir.path(), &format!("{text}{add}"));
        let o = fibresim(&["check", &scene]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(key) && err.contains("speed of light"), "{err}");
        assert!(o.stdout.is_empty());
    }
}

/// `--impact-speed V` times every collision at V (the approach speed of a
/// pair, the speed of a wall impact) instead of the energy bound.
#[test]
fn impact_speed_replaces_the_bound() {
    let out = stdout(&fibresim(&[
        "check",
        "scenarios/nine_fibres.toml",
        "--impact-speed",
        "3",
    ]));
    let f = TC1;
    let m_eff = f.worst_effective_mass();
    assert!(out.contains("impact speed given: v_max = 3e0 m/s"), "{out}");
    let pairs = table(&out, "t_Hertz (s)");
    let pair = row(&pairs, "fibre0 – fibre0 (same kind)");
    close(num(pair, "v_max (m/s)"), 3.0, "v_max of a pair");
    let t_h = hertz_time(m_eff / 2.0, f.d / 4.0, e_star(f.e, f.nu, f.e, f.nu), 3.0);
    close(num(pair, "t_Hertz (s)"), t_h, "t_Hertz of a pair");
    let wall = row(&pairs, "fibre0 – wall");
    close(
        num(wall, "t_Hertz (s)"),
        hertz_time(m_eff, f.d / 2.0, e_star(f.e, f.nu, 5e7, 0.23), 3.0),
        "t_Hertz on a wall",
    );
    let o = fibresim(&[
        "check",
        "scenarios/nine_fibres.toml",
        "--impact-speed",
        "-1",
    ]);
    assert_eq!(o.status.code(), Some(2));
}

/// Long body names do not push the columns out of line: every row of a
/// table is as long as its header, and each header cell starts where its
/// column does (numbers are right-aligned, so their column ends there).
#[test]
fn check_tables_stay_aligned_with_long_names() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/nine_fibres.toml"),
    )
    .unwrap()
    .replacen(
        "name = \"fibre0\"",
        "name = \"a_fibre_with_a_rather_long_name\"",
        1,
    );
    assert!(text.contains("a_fibre_with_a_rather_long_name"));
    let out = stdout(&fibresim(&["check", &write_scene(dir.path(), &text)]));
    for column in ["mass (kg)", "t_Hertz (s)"] {
        let lines: Vec<&str> = out
            .lines()
            .skip_while(|l| !l.contains(column))
            .take_while(|l| l.starts_with("  ") && !l.starts_with("  impact"))
            .collect();
        assert!(lines.len() >= 3, "{out}");
        let width = lines[0].chars().count();
        for l in &lines {
            assert_eq!(l.chars().count(), width, "{column}:\n{}", lines.join("\n"));
        }
    }
    let bodies = table(&out, "mass (kg)");
    assert_eq!(row(&bodies, "0")[1].1, "a_fibre_with_a_rather_long_name");
    let pairs = table(&out, "t_Hertz (s)");
    assert!(
        pairs
            .iter()
            .any(|r| r[0].1 == "a_fibre_with_a_rather_long_name – wall"),
        "{pairs:?}"
    );
}
