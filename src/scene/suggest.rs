//! Did-you-mean: the nearest names to a misspelt one by edit distance, for scene
//! names (`scene::load`), keys (`scene::validate`) and a shading sphere's scene
//! (`scene::shading_sphere`). A leaf: it imports nothing of the scene.

/// Optimal string alignment distance (Levenshtein with adjacent transpositions), in
/// characters.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, x) in d[0].iter_mut().enumerate() {
        *x = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = v;
        }
    }
    d[a.len()][b.len()]
}

/// The candidates nearest to `word` (all of those at the smallest distance, at most
/// three), if that distance is small: at most a third of the word's length (at least
/// 1, at most 3). A candidate that starts like the word (its prefix of the word's
/// length is that close) counts too, so `fvo` finds `fovy_deg` and `env-pattern`
/// finds both env-pattern scenes.
pub fn suggest<'a>(word: &str, candidates: &[&'a str]) -> Vec<&'a str> {
    let n = word.chars().count();
    let limit = (n / 3).clamp(1, 3);
    let dist = |c: &str| {
        let prefix: String = c.chars().take(n).collect();
        let p = if n >= 3 && c.chars().count() > n {
            edit_distance(word, &prefix)
        } else {
            usize::MAX
        };
        edit_distance(word, c).min(p)
    };
    let scored: Vec<(usize, &'a str)> = candidates
        .iter()
        .filter(|c| **c != word)
        .map(|c| (dist(c), *c))
        .filter(|(d, _)| *d <= limit)
        .collect();
    let Some(best) = scored.iter().map(|(d, _)| *d).min() else {
        return Vec::new();
    };
    scored
        .into_iter()
        .filter(|(d, _)| *d == best)
        .map(|(_, c)| c)
        .take(3)
        .collect()
}

/// "did you mean a?" / "did you mean a or b?" (empty when nothing is near), with
/// each name wrapped in `quote`.
pub fn did_you_mean(word: &str, candidates: &[&str], quote: &str) -> String {
    let s = suggest(word, candidates);
    let q: Vec<String> = s.iter().map(|c| format!("{quote}{c}{quote}")).collect();
    match q.len() {
        0 => String::new(),
        1 => format!("did you mean {}?", q[0]),
        _ => format!(
            "did you mean {} or {}?",
            q[..q.len() - 1].join(", "),
            q[q.len() - 1]
        ),
    }
}
