//! Units of two runs' channels made to match: the same unit, or the same base unit with
//! another SI prefix (kN and N, mm and m, ms and s), converted by the prefixes' ratio.
//! Anything else (g against m/s^2, where g might be a gram; deg against rad) is refused:
//! a guessed conversion is worse than none.

/// Base units a prefix may stand before (most specific first: `Nm` before `N`, `Pa`
/// before nothing).
const BASES: [&str; 12] = [
    "Nm", "N", "Pa", "Hz", "rad", "m", "s", "J", "W", "V", "A", "K",
];

/// SI prefixes and their factors (`u` and `µ` both micro).
const PREFIXES: [(&str, f64); 8] = [
    ("G", 1e9),
    ("M", 1e6),
    ("k", 1e3),
    ("c", 1e-2),
    ("m", 1e-3),
    ("u", 1e-6),
    ("µ", 1e-6),
    ("n", 1e-9),
];

/// (factor to the base, base) of a unit's numerator, `m/s^2` -> (1, "m"), `kN` ->
/// (1000, "N"); `None` when it is not a known base with at most one prefix.
fn split(numerator: &str) -> Option<(f64, &str)> {
    if let Some(b) = BASES.iter().find(|b| **b == numerator) {
        return Some((1.0, b));
    }
    PREFIXES.iter().find_map(|(p, f)| {
        let rest = numerator.strip_prefix(p)?;
        BASES.iter().find(|b| **b == rest).map(|b| (*f, *b))
    })
}

/// The factor that turns values in `from` into values in `to`: 1 for the same unit,
/// the prefixes' ratio for the same base unit (the same denominator, if any), `None`
/// otherwise.
pub fn factor(from: &str, to: &str) -> Option<f64> {
    if from == to {
        return Some(1.0);
    }
    let (fa, fb) = from.split_once('/').unwrap_or((from, ""));
    let (ta, tb) = to.split_once('/').unwrap_or((to, ""));
    if fb != tb {
        return None;
    }
    let ((ff, fbase), (tf, tbase)) = (split(fa)?, split(ta)?);
    (fbase == tbase).then_some(ff / tf)
}

#[cfg(test)]
mod tests {
    use super::factor;

    #[test]
    fn prefixes_of_one_base_convert_and_nothing_else() {
        assert_eq!(factor("kN", "N"), Some(1e3));
        assert_eq!(factor("mm", "m"), Some(1e-3));
        assert_eq!(factor("mm/s^2", "m/s^2"), Some(1e-3));
        assert_eq!(factor("kNm", "Nm"), Some(1e3));
        assert_eq!(factor("MPa", "kPa"), Some(1e3));
        assert_eq!(factor("N", "N"), Some(1.0));
        assert_eq!(factor("g", "m/s^2"), None);
        assert_eq!(factor("m/s", "m/s^2"), None);
        assert_eq!(factor("deg", "rad"), None);
        assert_eq!(factor("min", "s"), None);
        assert_eq!(factor("N", "m"), None);
    }
}
