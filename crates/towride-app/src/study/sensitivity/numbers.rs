//! Numbers as the study's page and charts show them: significant figures in plain
//! decimals where those read well, the sign always kept.

/// `x` to `n` significant figures: plain decimals for 0.001 <= |x| < 100000 (`4908`,
/// `-0.095`), else `1.23e-5`. Empty when `x` is not finite (the caller says why).
pub fn sig(x: f64, n: usize) -> String {
    if !x.is_finite() {
        return String::new();
    }
    if x == 0.0 {
        return "0".into();
    }
    let n = n.max(1);
    // The exponent after rounding: 9.996 to 3 figures is 10.0, not 9.996.
    let rounded: f64 = format!("{x:.prec$e}", prec = n - 1).parse().unwrap_or(x);
    let e = rounded.abs().log10().floor() as i32;
    if (-3..5).contains(&e) {
        let decimals = (n as i32 - 1 - e).max(0) as usize;
        format!("{rounded:.decimals$}")
    } else {
        format!("{rounded:.prec$e}", prec = n - 1)
    }
}

/// [`sig`] with a `+` on positive values: a figure whose sign is its meaning (an
/// elasticity raises or lowers its output).
pub fn signed(x: f64, n: usize) -> String {
    let s = sig(x, n);
    if x > 0.0 && x.is_finite() {
        format!("+{s}")
    } else {
        s
    }
}

/// An input value as its file gives it: every digit kept (the shortest text that reads
/// back as the same number), in plain decimals where that stays short.
pub fn exact(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-3..1e5).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `value unit`, or the value alone for a dimensionless unit (`-`, empty).
pub fn with_unit(value: &str, unit: &str) -> String {
    match unit.trim() {
        "" | "-" | "1" => value.to_string(),
        u => format!("{value} {u}"),
    }
}
