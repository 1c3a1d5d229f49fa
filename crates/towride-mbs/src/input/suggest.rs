//! "Did you mean" for names: the known names closest to a misspelt one, by edit
//! distance (insertions, deletions, substitutions and swaps of neighbours), close
//! enough to be a slip rather than another name.

/// Optimal string alignment distance between `a` and `b` (case-insensitive).
pub fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.to_lowercase().chars().collect();
    let b: Vec<char> = b.to_lowercase().chars().collect();
    let (n, m) = (a.len(), b.len());
    let mut d = vec![vec![0usize; m + 1]; n + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for j in 0..=m {
        d[0][j] = j;
    }
    for i in 1..=n {
        for j in 1..=m {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            d[i][j] = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d[i][j] = d[i][j].min(d[i - 2][j - 2] + 1);
            }
        }
    }
    d[n][m]
}

/// Up to three of `known` closest to `name`, nearest first: within a third of the
/// name's length (at least 2 edits), or containing it (a prefix left off).
pub fn closest<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let limit = (name.chars().count() / 3).max(2);
    let lower = name.to_lowercase();
    let mut scored: Vec<(usize, &str)> = known
        .into_iter()
        .filter_map(|k| {
            let d = distance(name, k);
            let inside = lower.len() >= 3 && k.to_lowercase().contains(&lower);
            (d <= limit || inside).then_some((if inside { d.min(limit) } else { d }, k))
        })
        .collect();
    scored.sort();
    scored.dedup();
    scored
        .into_iter()
        .take(3)
        .map(|(_, k)| k.to_string())
        .collect()
}

/// " (did you mean 'a', 'b'?)", or "" when nothing is close.
pub fn did_you_mean<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> String {
    let c = closest(name, known);
    if c.is_empty() {
        String::new()
    } else {
        let q: Vec<String> = c.iter().map(|s| format!("'{s}'")).collect();
        format!(" (did you mean {}?)", q.join(", "))
    }
}
