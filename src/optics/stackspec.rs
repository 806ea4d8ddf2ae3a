//! The one-line stack syntax of `ophis thinfilm --stack` and of the test data: layers outside in,
//! separated by commas, each `INDEX:THICKNESS` (thickness in nm, an optional `nm` suffix), and
//! periodic groups `(LAYER,LAYER,…)xCOUNT` (also `*COUNT`).
//!
//! ```text
//! 1.56:110,1.0:90                      two layers
//! (2.3:59.8,1.38:99.6)x10,2.3:59.8     a 10-pair Bragg mirror with a cap layer
//! keratin:95,(cauchy(1.6,8000):40,1.0+0.01i:120)x5,Ag:20
//! ```
//!
//! INDEX is anything [`Ior::parse`] reads: a number, `n+ki`, `keratin`, `cauchy(A,B)`, a named
//! dielectric or metal. Groups do not nest. Errors name the item (1-based, and the layer within a
//! group) with its text and what was expected.

use super::filmstack::{Layer, StackItem, MAX_REPEAT};
use super::ior::Ior;

/// Splits at commas outside parentheses.
fn split_top(s: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut depth, mut start) = (0i32, 0usize);
    for (i, c) in s.char_indices() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            ',' if depth == 0 => {
                out.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

fn layer(text: &str) -> Result<Layer, String> {
    let t = text.trim();
    let Some((n, d)) = t.rsplit_once(':') else {
        return Err("expected INDEX:THICKNESS (e.g. 1.56:110, thickness in nm)".into());
    };
    let ior = Ior::parse(n)?;
    let d_txt = d.trim();
    let d_num = d_txt.strip_suffix("nm").unwrap_or(d_txt).trim();
    match d_num.parse::<f64>() {
        Ok(v) if v >= 0.0 && v.is_finite() => Ok(Layer::new(ior, v)),
        _ => Err(format!(
            "the thickness '{d_txt}' is not a finite number ≥ 0 (nm)"
        )),
    }
}

/// Parses the layers (see the module doc).
pub fn parse_items(s: &str) -> Result<Vec<StackItem>, String> {
    if s.trim().is_empty() {
        return Err("the stack is empty: expected INDEX:THICKNESS,… (e.g. 1.56:110,1.0:90)".into());
    }
    let mut items = Vec::new();
    for (i, raw) in split_top(s).into_iter().enumerate() {
        let t = raw.trim();
        let at = |e: String| format!("item {} ('{t}'): {e}", i + 1);
        if t.is_empty() {
            return Err(at("empty; expected INDEX:THICKNESS or (…)xCOUNT".into()));
        }
        if !t.starts_with('(') {
            items.push(StackItem::Layer(layer(t).map_err(at)?));
            continue;
        }
        // A group: find its closing parenthesis.
        let mut depth = 0i32;
        let close = t.char_indices().find_map(|(j, c)| {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                _ => {}
            }
            (depth == 0).then_some(j)
        });
        let Some(close) = close else {
            return Err(at("the group's ')' is missing".into()));
        };
        let rest = t[close + 1..].trim();
        let count_txt = rest
            .strip_prefix('x')
            .or_else(|| rest.strip_prefix('*'))
            .or_else(|| rest.strip_prefix('×'))
            .ok_or_else(|| {
                at(format!(
                    "expected xCOUNT after the group's ')', got '{rest}'"
                ))
            })?;
        let count = count_txt
            .trim()
            .parse::<u32>()
            .ok()
            .filter(|c| (1..=MAX_REPEAT).contains(c))
            .ok_or_else(|| {
                at(format!(
                    "the repeat count '{}' is not a whole number from 1 to {MAX_REPEAT}",
                    count_txt.trim()
                ))
            })?;
        let mut period = Vec::new();
        for (j, lt) in split_top(&t[1..close]).into_iter().enumerate() {
            let lt = lt.trim();
            let at_l =
                |e: String| format!("item {}, layer {} of the group ('{lt}'): {e}", i + 1, j + 1);
            if lt.starts_with('(') {
                return Err(at_l("groups cannot nest".into()));
            }
            period.push(layer(lt).map_err(at_l)?);
        }
        items.push(StackItem::Periodic { period, count });
    }
    Ok(items)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::filmstack::FilmStack;

    #[test]
    fn parses_layers_groups_and_reads_back_its_display() {
        let items = parse_items("1.56:110, 1.0:90nm").unwrap();
        assert_eq!(
            items,
            vec![
                StackItem::Layer(Layer::new(Ior::Real(1.56), 110.0)),
                StackItem::Layer(Layer::new(Ior::Real(1.0), 90.0)),
            ]
        );
        let s = "keratin:95,(cauchy(1.6,8000):40,1+0.01i:120)x5,Ag:20";
        let items = parse_items(s).unwrap();
        assert_eq!(items.len(), 3);
        assert_eq!(items[1].count(), 5);
        assert_eq!(items[1].period()[0].ior, Ior::Cauchy { a: 1.6, b: 8000.0 });
        let st = FilmStack::new(Ior::Real(1.0), items, Ior::Real(1.5)).unwrap();
        assert_eq!(st.n_layers(), 12);
        assert_eq!(st.to_string(), s);
        assert_eq!(parse_items(&st.to_string()).unwrap(), st.items());
        assert_eq!(parse_items("(2.3:60,1.38:100)*10").unwrap()[0].count(), 10);
    }

    #[test]
    fn errors_name_the_item_and_what_was_expected() {
        crate::test_util::assert_rejects(
            parse_items,
            &[
                ("", "empty"),
                ("1.56:110,", "item 2"),
                ("1.56", "INDEX:THICKNESS"),
                ("1.56:abc", "item 1 ('1.56:abc'): the thickness 'abc'"),
                ("1.56:-5", "≥ 0"),
                ("1.56:inf", "finite"),
                (
                    "1.0:10,glass:100",
                    "item 2 ('glass:100'): 'glass' is not an index",
                ),
                ("(1.5:10,1.2:20", "')' is missing"),
                ("(1.5:10,1.2:20)", "expected xCOUNT"),
                ("(1.5:10)x0", "repeat count '0'"),
                ("(1.5:10)x1.5", "whole number"),
                ("(1.5:10,x:3)x2", "item 1, layer 2 of the group ('x:3')"),
                ("((1.5:10)x2)x2", "cannot nest"),
                ("1.5-1i:10", "gain"),
            ],
        );
        // Too many layers once repeats are written out: the stack constructor says so.
        let items = parse_items("(1.5:10,1.2:10)x4096").unwrap();
        let e = FilmStack::new(Ior::Real(1.0), items, Ior::Real(1.0)).unwrap_err();
        assert!(e.contains("item 1") && e.contains("4096 layers"), "{e}");
    }
}
