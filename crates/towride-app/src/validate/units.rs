//! Units of recorded channels as loggers write them: accelerations in `m/s^2` or in
//! multiples of standard gravity (`g`, `gn`), speeds in `km/h`, `m/s` or `mph`, time in
//! `s` or `ms`.

use super::G_MPS2;

/// Physical unit of a recorded acceleration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unit {
    /// Metres per second squared.
    Mps2,
    /// Multiples of standard gravity, 9.80665 m/s^2 (`g`, `gn`).
    G,
}

impl Unit {
    /// Parses `m/s^2` (also `m/s2`, `m/s²`, `m s^-2`), `g` or `gn` (any case).
    pub fn parse(s: &str) -> Option<Unit> {
        match s.trim() {
            "m/s^2" | "m/s2" | "m/s²" | "m s^-2" | "m*s^-2" => Some(Unit::Mps2),
            u if u.eq_ignore_ascii_case("g") || u.eq_ignore_ascii_case("gn") => Some(Unit::G),
            _ => None,
        }
    }

    /// Factor to m/s^2.
    pub fn to_si(self) -> f64 {
        match self {
            Unit::Mps2 => 1.0,
            Unit::G => G_MPS2,
        }
    }

    /// The unit as written in reports: "m/s^2" or "g".
    pub fn label(self) -> &'static str {
        match self {
            Unit::Mps2 => "m/s^2",
            Unit::G => "g",
        }
    }
}

/// Physical unit of a recorded speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpeedUnit {
    /// Kilometres per hour.
    Kmh,
    /// Metres per second.
    Mps,
    /// Miles per hour (international mile, 1609.344 m).
    Mph,
}

impl SpeedUnit {
    /// Parses `km/h` (also `kmh`, `kph`), `m/s` or `mph`.
    pub fn parse(s: &str) -> Option<SpeedUnit> {
        match s.trim().to_ascii_lowercase().as_str() {
            "km/h" | "kmh" | "kph" | "km h^-1" => Some(SpeedUnit::Kmh),
            "m/s" | "m s^-1" => Some(SpeedUnit::Mps),
            "mph" | "mi/h" => Some(SpeedUnit::Mph),
            _ => None,
        }
    }

    /// Factor to m/s.
    pub fn to_si(self) -> f64 {
        match self {
            SpeedUnit::Kmh => 1.0 / 3.6,
            SpeedUnit::Mps => 1.0,
            SpeedUnit::Mph => 1609.344 / 3600.0,
        }
    }

    /// The unit as written in reports.
    pub fn label(self) -> &'static str {
        match self {
            SpeedUnit::Kmh => "km/h",
            SpeedUnit::Mps => "m/s",
            SpeedUnit::Mph => "mph",
        }
    }
}

/// Factor of a time unit to seconds: `s` (also `sec`) or `ms`.
pub fn time_factor(u: &str) -> Option<f64> {
    match u.trim() {
        "s" | "sec" | "S" => Some(1.0),
        "ms" => Some(1e-3),
        _ => None,
    }
}

/// True when `s` names a unit this module knows (a units row under a header).
pub fn known(s: &str) -> bool {
    Unit::parse(s).is_some() || SpeedUnit::parse(s).is_some() || time_factor(s).is_some()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn logger_units() {
        assert_eq!(Unit::parse("gn"), Some(Unit::G));
        assert_eq!(Unit::parse("G"), Some(Unit::G));
        assert_eq!(Unit::parse("m/s²"), Some(Unit::Mps2));
        assert_eq!(SpeedUnit::parse("km/h"), Some(SpeedUnit::Kmh));
        assert!((SpeedUnit::Mph.to_si() - 0.44704).abs() < 1e-12);
        assert_eq!(time_factor("ms"), Some(1e-3));
        assert!(!known("bar"));
    }
}
