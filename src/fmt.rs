//! Numbers in messages: short enough to read, exact enough to act on.
//!
//! A computed value shows the rounding of binary arithmetic in its shortest
//! round-trip form (`501 × 1e-6` is `5.009999999999999e-4`). Rounded to 12
//! significant digits it reads as the user would write it (`5.01e-4`):
//! twelve digits keep every decimal a user types in a scenario and drop
//! only the last three or four digits of a double, where arithmetic rounds.
//! Data files (CSV, JSON, body files) keep every digit; this is for text
//! that people read.

/// `x` to at most 12 significant digits, in the shorter of its plain
/// (`0.025`, `1100`) and scientific (`5.01e-4`, `1e5`) forms; plain on a
/// tie. `NaN`, `inf` and `-inf` as Rust writes them.
pub fn short(x: f64) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    // `{:.11e}` rounds to 12 significant digits (correctly, in decimal);
    // reading it back gives the double nearest that decimal, whose shortest
    // round-trip form has no digits beyond it.
    let r: f64 = format!("{x:.11e}").parse().unwrap_or(x);
    let plain = r.to_string();
    let sci = format!("{r:e}");
    if sci.len() < plain.len() {
        sci
    } else {
        plain
    }
}

/// Three numbers as `[x, y, z]`, each [`short`].
pub fn short3(v: impl Into<[f64; 3]>) -> String {
    let [x, y, z] = v.into();
    format!("[{}, {}, {}]", short(x), short(y), short(z))
}

/// "12 fibres", "1 sphere", "900 fibres and 100 spheres": what a scene or a
/// frame holds, for messages and titles.
pub fn census(fibres: usize, spheres: usize) -> String {
    let count = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    match (fibres, spheres) {
        (_, 0) => count(fibres, "fibre"),
        (0, _) => count(spheres, "sphere"),
        _ => format!(
            "{} and {}",
            count(fibres, "fibre"),
            count(spheres, "sphere")
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{census, short, short3};

    #[test]
    fn arithmetic_rounding_is_hidden() {
        // t = n·δt of a run stopped at step 501.
        assert_eq!(501.0 * 1e-6, 5.009999999999999e-4);
        assert_eq!(short(501.0 * 1e-6), "5.01e-4");
        assert_eq!(short(7.50025000000001e-3), "0.00750025");
        assert_eq!(short(75_000.0 * 2e-5), "1.5");
        assert_eq!(short(0.1 + 0.2), "0.3");
    }

    #[test]
    fn twelve_digits_survive_and_no_more() {
        assert_eq!(short(0.123456789012), "0.123456789012");
        assert_eq!(short(0.1234567890123), "0.123456789012");
        assert_eq!(short(-2.010825317547305), "-2.01082531755");
        assert_eq!(short(123456789012.0), "123456789012");
        // Trailing zeros of a large integer are not significant digits.
        assert_eq!(short(1234567890123.0), "1234567890120");
        assert_eq!(short(1.234567890123e20), "1.23456789012e20");
    }

    #[test]
    fn the_shorter_form_is_chosen() {
        for (x, want) in [
            (1e-6, "1e-6"),
            (1e-3, "1e-3"),
            (0.01, "0.01"),
            (0.025, "0.025"),
            (0.5, "0.5"),
            (0.0, "0"),
            (-0.35, "-0.35"),
            (10.0, "10"),
            (1100.0, "1100"),
            (1e5, "1e5"),
            (5e7, "5e7"),
            (1.2e12, "1.2e12"),
            (1e300, "1e300"),
            (2.5e-300, "2.5e-300"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(short(x), want, "{x:e}");
        }
        assert_eq!(short3([0.0, -4.5, 0.1 + 0.2]), "[0, -4.5, 0.3]");
    }

    #[test]
    fn short_hides_the_rounding_of_n_dt_and_nothing_else() {
        assert_eq!(75_000.0 * 2e-5, 1.5000000000000002);
        assert_eq!(short(75_000.0 * 2e-5), "1.5");
        assert_eq!(short(39_000.0 * 2e-5), "0.78");
        // 12 significant digits survive.
        assert_eq!(short(0.123456789012), "0.123456789012");
        assert_eq!(short(2.5e-300), "2.5e-300");
    }

    /// Counts read as a person writes them.
    #[test]
    fn a_census_names_fibres_and_spheres() {
        assert_eq!(census(1, 0), "1 fibre");
        assert_eq!(census(0, 0), "0 fibres");
        assert_eq!(census(0, 2), "2 spheres");
        assert_eq!(census(2, 1), "2 fibres and 1 sphere");
    }
}
