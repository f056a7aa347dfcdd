//! `trajectory.csv`: its columns, one row per body per cadence,
//! and a round trip: the last row is `summary.json`'s final state bit for
//! bit (x, q, v), its world angular velocity the summary's body-frame one
//! rotated by R(q) (a rotation matrix here, not the library's rotation).

use crate::common;
use common::fibresim;
use std::path::Path;

fn rows(p: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(p).unwrap();
    let h = r.headers().unwrap().iter().map(str::to_string).collect();
    let rows = r
        .records()
        .map(|x| x.unwrap().iter().map(str::to_string).collect())
        .collect();
    (h, rows)
}

fn nums(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect()
}

fn round_trip(scenario: &str, extra: &[&str], bodies: usize, rows_per_body: usize) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let mut a = vec!["run", scenario, "-q", "--out", out.to_str().unwrap()];
    a.extend(extra);
    let o = fibresim(&a);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (h, rows) = rows(&out.join("trajectory.csv"));
    assert_eq!(
        h,
        [
            "step", "t", "body", "x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx",
            "wy", "wz"
        ]
    );
    assert_eq!(rows.len(), bodies * rows_per_body);
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let last = &rows[rows.len() - bodies..];
    for (row, f) in last.iter().zip(s["final"].as_array().unwrap()) {
        assert_eq!(row[0].parse::<u64>().unwrap(), s["steps"].as_u64().unwrap());
        assert_eq!(row[2].parse::<u64>().unwrap(), f["body"].as_u64().unwrap());
        let got: Vec<f64> = row[3..13].iter().map(|c| c.parse().unwrap()).collect();
        let want: Vec<f64> = [nums(&f["x"]), nums(&f["q"]), nums(&f["v"])].concat();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&got),
            bits(&want),
            "x, q, v of body {} bit for bit",
            f["body"]
        );
        // ω_world = R(q) ω_body, to the formulas' rounding and ‖q‖ − 1 (≤ 1e-13).
        let [w, x, y, z] = [want[3], want[4], want[5], want[6]];
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
        let wb = nums(&f["omega_body"]);
        let scale = wb.iter().map(|c| c.abs()).fold(0.0, f64::max).max(1e-300);
        for i in 0..3 {
            let ww: f64 = (0..3).map(|j| r[i][j] * wb[j]).sum();
            let got: f64 = row[13 + i].parse().unwrap();
            assert!(
                (got - ww).abs() <= 1e-12 * scale,
                "w[{i}] {got} against R(q) omega_body {ww}"
            );
        }
    }
}

#[test]
fn the_last_row_of_a_contact_scene_is_the_summary_bit_for_bit() {
    // 0.03 s of test case 2: 300000 steps, a row per body every 10000 (31 rows).
    round_trip(
        "scenarios/nine_fibres.toml",
        &["--t-end", "0.03", "--trajectory-every", "10000"],
        9,
        31,
    );
}

#[test]
fn the_last_row_of_a_torque_scene_is_the_summary_bit_for_bit() {
    // Test case 4: 1e5 steps; cadence 30000 leaves an off-cadence last row (0, 30000, 60000, 90000, 100000).
    round_trip(
        "scenarios/torque_fibre.toml",
        &["--trajectory-every", "30000"],
        1,
        5,
    );
}

#[test]
fn a_sphere_scene_writes_its_trajectory_too() {
    round_trip(
        "scenarios/torque_sphere.toml",
        &["--trajectory-every", "5000"],
        1,
        3,
    );
}
