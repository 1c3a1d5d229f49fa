//! How channels are shown to a reader, in one place for every figure, page and listing:
//! units in their display form (`m/s²` for the CSV header's ASCII `m/s^2`), angles in
//! degrees on figures (the CSV and the summary keep SI radians), and channels in
//! natural order (`hitch_eta_2` before `hitch_eta_10`).

use std::cmp::Ordering;

/// The display form of an ASCII unit as written in a CSV header: powers as superscripts
/// (`m/s^2` -> `m/s²`, `kg m^2` -> `kg m²`, `s^-1` -> `s⁻¹`); everything else unchanged.
pub fn display_unit(ascii: &str) -> String {
    let mut out = String::with_capacity(ascii.len() + 4);
    let mut chars = ascii.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '^' {
            out.push(c);
            continue;
        }
        // An exponent: an optional minus sign and digits; a lone '^' stays as it is.
        let mut sup = String::new();
        if chars.peek() == Some(&'-') {
            chars.next();
            sup.push('⁻');
        }
        while let Some(d) = chars.peek().and_then(|d| d.to_digit(10)) {
            chars.next();
            sup.push(SUPERSCRIPT[d as usize]);
        }
        if sup.is_empty() || sup == "⁻" {
            out.push('^');
            if sup == "⁻" {
                out.push('-');
            }
        } else {
            out.push_str(&sup);
        }
    }
    out
}

const SUPERSCRIPT: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

/// A channel's unit as a figure shows it: the factor its SI values are multiplied by and
/// the display unit. Angles (`rad`, `rad/s`, `rad/s^2`) in degrees, the unit an engineer
/// reads pitch and roll in; every other unit as it is ([`display_unit`]).
pub fn figure_unit(ascii: &str) -> (f64, String) {
    match ascii.strip_prefix("rad") {
        Some(rest) if rest.is_empty() || rest.starts_with('/') => (
            180.0 / std::f64::consts::PI,
            display_unit(&format!("deg{rest}")),
        ),
        _ => (1.0, display_unit(ascii)),
    }
}

/// One part of a [`NaturalKey`]: a run of digits by its value, or text.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Part {
    // Numbers before text, as in a file manager ("a_1" before "a_b").
    Number(u128, usize),
    Text(String),
}

/// The key that sorts names in natural order: runs of digits compare by value
/// (`hitch_eta_2` < `hitch_eta_10`), the rest by character. Equal values with different
/// leading zeros (`m01`, `m1`) order by their digit count, so the order stays total.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct NaturalKey(Vec<Part>);

/// The natural-order key of `name` ([`NaturalKey`]).
pub fn natural_key(name: &str) -> NaturalKey {
    let mut parts = Vec::new();
    let mut rest = name;
    while !rest.is_empty() {
        let digits = rest
            .find(|c: char| !c.is_ascii_digit())
            .unwrap_or(rest.len());
        if digits > 0 {
            let (num, tail) = rest.split_at(digits);
            // More digits than u128 holds: saturate (such names do not occur as channels).
            parts.push(Part::Number(num.parse().unwrap_or(u128::MAX), num.len()));
            rest = tail;
        } else {
            let text = rest
                .find(|c: char| c.is_ascii_digit())
                .unwrap_or(rest.len());
            let (t, tail) = rest.split_at(text);
            parts.push(Part::Text(t.to_string()));
            rest = tail;
        }
    }
    NaturalKey(parts)
}

/// `a` against `b` in natural order ([`natural_key`]).
pub fn natural_cmp(a: &str, b: &str) -> Ordering {
    natural_key(a).cmp(&natural_key(b))
}

/// Sorts names (or anything with a name) in natural order, stably.
pub fn sort_natural<T>(items: &mut [T], name: impl Fn(&T) -> &str) {
    items.sort_by_cached_key(|x| natural_key(name(x)));
}

/// Serialises a map keyed by channel name in natural order (JSON keeps the order it is
/// written in, and the pages list channels in that order).
pub fn serialize_natural<S, V>(
    map: &std::collections::BTreeMap<String, V>,
    s: S,
) -> Result<S::Ok, S::Error>
where
    S: serde::Serializer,
    V: serde::Serialize,
{
    use serde::ser::SerializeMap;
    let mut entries: Vec<(&String, &V)> = map.iter().collect();
    sort_natural(&mut entries, |e| e.0.as_str());
    let mut m = s.serialize_map(Some(entries.len()))?;
    for (k, v) in entries {
        m.serialize_entry(k, v)?;
    }
    m.end()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_and_order() {
        assert_eq!(display_unit("m/s^2"), "m/s²");
        assert_eq!(display_unit("kg m^2"), "kg m²");
        assert_eq!(display_unit("s^-1"), "s⁻¹");
        assert_eq!(display_unit("N"), "N");
        assert_eq!(figure_unit("rad/s^2").1, "deg/s²");
        assert_eq!(figure_unit("radius").0, 1.0);
        assert_eq!(natural_cmp("x10", "x9"), Ordering::Greater);
        assert_eq!(natural_cmp("m01", "m1"), Ordering::Greater);
    }
}
