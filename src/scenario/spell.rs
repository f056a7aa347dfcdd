//! "Did you mean": the known name closest to a misspelt one, for unknown
//! tables, keys and enumerated values of a scenario file.

/// Edits (insert, delete, substitute, swap two neighbours) from `a` to `b`:
/// the optimal-string-alignment distance, so that the commonest typo, two
/// letters swapped (`fiber`, `restitutoin`), counts as one edit.
pub(crate) fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // d[i][j]: distance of a[..i] and b[..j]; three rows suffice.
    let mut before = vec![0; b.len() + 1];
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut row = vec![0; b.len() + 1];
    for i in 1..=a.len() {
        row[0] = i;
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut d = (prev[j - 1] + cost).min(prev[j] + 1).min(row[j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(before[j - 2] + 1);
            }
            row[j] = d;
        }
        std::mem::swap(&mut before, &mut prev);
        std::mem::swap(&mut prev, &mut row);
    }
    prev[b.len()]
}

/// The candidate closest to `word`, if it is close enough to be a typo of
/// it: at most a third of its letters edited (at least one edit allowed,
/// as rustc does for names); else the shortest candidate that begins with
/// a `word` of three letters or more (`overlap` for `overlap_ratio`).
/// Letter case is ignored (`Fibre`). Ties go to the first candidate.
pub(crate) fn closest<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let w = word.to_lowercase();
    let limit = (w.chars().count() / 3).max(1);
    let candidates: Vec<(String, &str)> = candidates
        .into_iter()
        .map(|c| (c.to_lowercase(), c))
        .collect();
    let typo = candidates
        .iter()
        .map(|(l, c)| (distance(&w, l), *c))
        .filter(|&(d, _)| d <= limit)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c);
    typo.or_else(|| {
        candidates
            .iter()
            .filter(|(l, _)| w.chars().count() >= 3 && l.starts_with(&w))
            .min_by_key(|(l, _)| l.len())
            .map(|&(_, c)| c)
    })
}

/// `did you mean `x`? ` when a candidate is close to `word`, else nothing.
pub(crate) fn did_you_mean<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> String {
    closest(word, candidates).map_or(String::new(), |c| format!("did you mean `{c}`? "))
}

#[cfg(test)]
mod tests {
    use super::{closest, distance};

    #[test]
    fn distances() {
        assert_eq!(distance("", ""), 0);
        assert_eq!(distance("densty", "density"), 1);
        assert_eq!(distance("fiber", "fibre"), 1);
        assert_eq!(distance("restitutoin", "restitution"), 1);
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("", "abc"), 3);
        assert_eq!(distance("abc", ""), 3);
    }

    #[test]
    fn typos_are_matched_and_strangers_are_not() {
        let shapes = ["fibre", "sphere", "rigid"];
        assert_eq!(closest("fiber", shapes), Some("fibre"));
        assert_eq!(closest("Fibre", shapes), Some("fibre"));
        assert_eq!(closest("cylinder", shapes), None);
        assert_eq!(closest("pcdmm", ["pcdm", "rk4"]), Some("pcdm"));
        assert_eq!(
            closest("simulaton", ["simulation", "world"]),
            Some("simulation")
        );
        assert_eq!(closest("colour", ["name", "shape", "length"]), None);
        // The nearest wins: `bodys` is one edit from `body`, two from `bodies`.
        assert_eq!(closest("bodys", ["bodies", "body"]), Some("body"));
        // A beginning names the key it begins, not one it is inside.
        let guards = ["energy_error_pct", "overlap_ratio", "start_overlap_ratio"];
        assert_eq!(closest("overlap", guards), Some("overlap_ratio"));
        assert_eq!(closest("ov", guards), None);
    }
}
