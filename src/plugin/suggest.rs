//! "Did you mean …?": the known names nearest to a misspelt one.

/// Edit distance between two strings (insertions, deletions, substitutions and swaps of
/// neighbouring characters each cost 1; case differences cost nothing, so `intIOR` is next to
/// `int_ior`'s 0.6 spelling).
fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().flat_map(char::to_lowercase).collect();
    let b: Vec<char> = b.chars().flat_map(char::to_lowercase).collect();
    // Optimal-string-alignment distance over three rolling rows.
    let mut prev2 = vec![0usize; b.len() + 1];
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0usize; b.len() + 1];
    for i in 1..=a.len() {
        cur[0] = i;
        for j in 1..=b.len() {
            let cost = (a[i - 1] != b[j - 1]) as usize;
            let mut d = (prev[j] + 1).min(cur[j - 1] + 1).min(prev[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(prev2[j - 2] + 1);
            }
            cur[j] = d;
        }
        std::mem::swap(&mut prev2, &mut prev);
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// Up to three known names close to `name` (within a third of its length, at least 2 edits),
/// nearest first; a known name that `name` contains or is contained in also counts.
pub fn nearest<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> Vec<&'a str> {
    let limit = (name.chars().count() / 3).max(2);
    let lower = name.to_lowercase();
    let mut scored: Vec<(usize, &str)> = known
        .into_iter()
        .filter_map(|k| {
            let d = distance(name, k);
            let kl = k.to_lowercase();
            let sub =
                kl.len() >= 3 && lower.len() >= 3 && (kl.contains(&lower) || lower.contains(&kl));
            (d <= limit || sub).then_some((d, k))
        })
        .collect();
    scored.sort();
    scored.dedup_by(|a, b| a.1 == b.1);
    scored.into_iter().take(3).map(|(_, k)| k).collect()
}

/// " (did you mean 'a' or 'b'?)", or "" when nothing is near.
pub fn did_you_mean<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> String {
    let near = nearest(name, known);
    match near.as_slice() {
        [] => String::new(),
        [a] => format!(" (did you mean '{a}'?)"),
        [rest @ .., last] => {
            let q: Vec<String> = rest.iter().map(|s| format!("'{s}'")).collect();
            format!(" (did you mean {} or '{last}'?)", q.join(", "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        assert_eq!(distance("roughconductr", "roughconductor"), 1);
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("ab", "ba"), 1);
        assert_eq!(distance("intIOR", "intior"), 0);
        assert_eq!(distance("", "abc"), 3);
    }

    #[test]
    fn suggestions() {
        let known = ["roughconductor", "conductor", "roughdielectric", "diffuse"];
        assert_eq!(nearest("roughconductr", known), vec!["roughconductor"]);
        assert_eq!(did_you_mean("difuse", known), " (did you mean 'diffuse'?)");
        assert_eq!(did_you_mean("xyzzy", known), "");
        // A name that contains a known one (a plugin-prefixed spelling) is near it.
        assert!(nearest("alpha_uv", ["alpha_u", "alpha_v", "eta"]).contains(&"alpha_u"));
    }
}
