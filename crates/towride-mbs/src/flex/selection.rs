//! Which modes a modal body keeps: all, below a frequency cutoff, an explicit list, or
//! the a-priori load-path rule.
//!
//! # The load-path rule
//!
//! Loads enter a body at its interface nodes. For each loaded interface i and each of
//! its six directions d, apply a unit load there with all *other* interface nodes held:
//! the static response is the load path from i into the supports. Its generalised
//! forces on the orthonormal elastic modes are p_k = ω_k² η_k, with η_k the modal
//! coordinates of the held static solution (the applied load plus the support
//! reactions, a self-equilibrated set, so no rigid-body part). Mode k stores
//! E_k = p_k² / (2 ω_k²) of that response's strain energy (the energies add up to the
//! total in a mass-orthonormal basis). Over an excitation band [f_lo, f_hi] each mode
//! responds A_k times its static share, A_k = max over the band of
//! 1 / sqrt((1 - r²)² + (2 ζ_k r)²), r = f / f_k (single-degree-of-freedom
//! amplification with the mode's damping). The weighted share is
//!
//!   s_k(i, d) = A_k² p_k² / ω_k² / Σ_m A_m² p_m² / ω_m²,
//!
//! and mode k is kept when max over (i, d) of s_k reaches `min_energy_share`. So a mode
//! is kept when it stores a noticeable part of the strain energy of some interface load
//! path, amplified if the band reaches it; it needs no simulation, unlike the
//! strain-energy method of the commercial tool (which ranks modes by their share in a run
//! that has already converged). With a single interface (nothing to hold) the free
//! body's inertia-relief response is used: p_k = φ_k(i, d).

use super::FlexError;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::input::{RuleIn, SelectionIn};
use super::modal::{ModalData, NodeKind};
use crate::input::{InputError, Seg, Source};

/// Default strain-energy share for the load-path rule.
pub const DEFAULT_MIN_ENERGY_SHARE: f64 = 0.01;

/// Which elastic modes of a modal body are kept.
#[derive(Clone, Debug, PartialEq)]
pub enum Rule {
    /// Every elastic mode.
    All,
    /// Elastic modes up to `max_hz`.
    Cutoff {
        /// Highest kept frequency [Hz].
        max_hz: f64,
    },
    /// Mode numbers of the mode table (1-based, rigid-body modes 1..6 excluded).
    List {
        /// The mode numbers to keep.
        modes: Vec<usize>,
    },
    /// The a-priori load-path rule (see the module documentation).
    LoadPath(LoadPath),
}

/// Settings of the load-path rule.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadPath {
    /// Excitation band [f_lo, f_hi] over which the modal amplification is taken [Hz].
    pub band_hz: [f64; 2],
    /// Weighted strain-energy share (a fraction, not %) a mode must reach in some load
    /// case to be kept.
    pub min_energy_share: f64,
    /// Interfaces where loads enter; empty: all.
    pub load_interfaces: Vec<String>,
    /// Unit moments as well as unit forces (false: forces only, as through a ball joint).
    pub load_moments: bool,
    /// Expected load mix at the loaded interfaces (body axes) [N]: one combined case.
    pub load_n: Option<[f64; 3]>,
}

impl Rule {
    /// Reads a selection table found at `base` of `src` (`[selection]` in a flex file).
    pub fn from_input(
        src: &Source,
        base: &[Seg],
        s: &SelectionIn,
        interfaces: &[String],
    ) -> Result<Rule, InputError> {
        let at = |k: &str| {
            let mut v = base.to_vec();
            v.push(Seg::from(k));
            v
        };
        match s.rule {
            RuleIn::All => Ok(Rule::All),
            RuleIn::Cutoff => {
                let c = s
                    .cutoff_hz
                    .ok_or_else(|| src.error(&at("cutoff_hz"), "missing for rule = \"cutoff\""))?;
                Ok(Rule::Cutoff {
                    max_hz: src.positive(&at("cutoff_hz"), c)?,
                })
            }
            RuleIn::List => {
                let modes = s
                    .modes
                    .clone()
                    .ok_or_else(|| src.error(&at("modes"), "missing for rule = \"list\""))?;
                if let Some(j) = modes.iter().position(|&m| m <= 6) {
                    return Err(src.error(
                        &[at("modes"), vec![Seg::from(j)]].concat(),
                        "modes 1..6 are the rigid-body modes; elastic modes start at 7",
                    ));
                }
                Ok(Rule::List { modes })
            }
            RuleIn::LoadPath => {
                let band = s
                    .band_hz
                    .ok_or_else(|| src.error(&at("band_hz"), "missing for rule = \"load_path\""))?;
                src.non_negative(&at("band_hz"), band[0])?;
                src.finite(&at("band_hz"), band[1])?;
                if band[1] <= band[0] {
                    return Err(src.error(&at("band_hz"), "must be [low, high] with low < high"));
                }
                let share = s.min_energy_share.unwrap_or(DEFAULT_MIN_ENERGY_SHARE);
                let share = src.positive(&at("min_energy_share"), share)?;
                if share >= 1.0 {
                    return Err(src.error(
                        &at("min_energy_share"),
                        "is a fraction of the strain energy, below 1",
                    ));
                }
                let load_interfaces = s.load_interfaces.clone().unwrap_or_default();
                for (j, n) in load_interfaces.iter().enumerate() {
                    if !interfaces.contains(n) {
                        return Err(src.error(
                            &[at("load_interfaces"), vec![Seg::from(j)]].concat(),
                            format!("names a missing interface `{n}`"),
                        ));
                    }
                }
                if let Some(l) = s.load_n {
                    for (c, x) in l.iter().enumerate() {
                        src.finite(&[at("load_n"), vec![Seg::from(c)]].concat(), *x)?;
                    }
                    if l.iter().all(|x| *x == 0.0) {
                        return Err(src.error(&at("load_n"), "is all zero"));
                    }
                }
                Ok(Rule::LoadPath(LoadPath {
                    band_hz: band,
                    min_energy_share: share,
                    load_interfaces,
                    load_moments: s.load_moments.unwrap_or(true),
                    load_n: s.load_n,
                }))
            }
        }
    }

    /// The rule in words, for reports.
    pub fn describe(&self) -> String {
        match self {
            Rule::All => "all elastic modes".into(),
            Rule::Cutoff { max_hz } => format!("frequency cutoff {max_hz} Hz"),
            Rule::List { modes } => format!("explicit list {modes:?}"),
            Rule::LoadPath(l) => format!(
                "load paths ({}) from {}, band {}-{} Hz, energy share >= {} %",
                if l.load_moments {
                    "forces and moments"
                } else {
                    "forces"
                },
                if l.load_interfaces.is_empty() {
                    "all interfaces".to_string()
                } else {
                    l.load_interfaces.join(", ")
                },
                l.band_hz[0],
                l.band_hz[1],
                100.0 * l.min_energy_share
            ),
        }
    }
}

/// One load case of the load-path rule and the weighted energy shares of every mode.
#[derive(Clone, Debug)]
pub struct LoadCase {
    /// Interface node where the unit load is applied.
    pub interface: String,
    /// 0..3 forces along x, y, z; 3..6 moments about x, y, z; 6 the combined `load_n`.
    pub direction: usize,
    /// Weighted strain-energy share of each elastic mode (they add up to 1).
    pub shares: Vec<f64>,
}

/// The outcome of a selection.
#[derive(Clone, Debug)]
pub struct Selection {
    /// Per elastic mode (in `ModalData::modes` order): kept or not.
    pub selected: Vec<bool>,
    /// Load-path rule only: per mode the largest share over the load cases.
    pub max_share: Option<Vec<f64>>,
    /// Load-path rule only: every load case with its shares (empty for other rules).
    pub cases: Vec<LoadCase>,
}

/// Largest single-degree-of-freedom amplification |H(f)| / |H(0)| over the band.
pub fn band_amplification(f_mode: f64, zeta: f64, band_hz: [f64; 2]) -> f64 {
    let h = |r: f64| 1.0 / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt();
    let (lo, hi) = (band_hz[0] / f_mode, band_hz[1] / f_mode);
    let mut a = h(lo).max(h(hi));
    if zeta * zeta < 0.5 {
        let peak = (1.0 - 2.0 * zeta * zeta).sqrt();
        if lo <= peak && peak <= hi {
            a = a.max(h(peak));
        }
    }
    a
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0)
}

/// Rows of the six interface DOFs of node `n` in the coordinates
/// z = (rigid translation a, rigid rotation theta about the origin, modal eta).
fn interface_rows(body: &ModalData, n: usize) -> DMatrix<f64> {
    let nm = body.modes.len();
    let node = &body.nodes[n];
    let mut g = DMatrix::zeros(6, 6 + nm);
    let x = Vector3::from(node.position_m);
    // u = a + theta x x = a - [x] theta; rotation = theta.
    let sx = skew(&x);
    for i in 0..3 {
        g[(i, i)] = 1.0;
        g[(3 + i, 3 + i)] = 1.0;
        for j in 0..3 {
            g[(i, 3 + j)] = -sx[(i, j)];
        }
    }
    for (k, s) in node.shapes.iter().enumerate() {
        for i in 0..6 {
            g[(i, 6 + k)] = s[i];
        }
    }
    g
}

/// Weighted strain-energy shares of every mode for every load case of `rule`.
pub fn load_path_cases(body: &ModalData, rule: &LoadPath) -> Result<Vec<LoadCase>, FlexError> {
    let nm = body.modes.len();
    let interfaces: Vec<usize> = (0..body.nodes.len())
        .filter(|&n| body.nodes[n].kind == NodeKind::Interface)
        .collect();
    let loaded: Vec<usize> = if rule.load_interfaces.is_empty() {
        interfaces.clone()
    } else {
        rule.load_interfaces
            .iter()
            .map(|name| {
                interfaces
                    .iter()
                    .copied()
                    .find(|&n| &body.nodes[n].name == name)
                    .ok_or_else(|| FlexError::Selection(format!("no interface `{name}`")))
            })
            .collect::<Result<_, _>>()?
    };
    let amp: Vec<f64> = body
        .modes
        .iter()
        .map(|m| band_amplification(m.frequency_hz, m.damping_ratio, rule.band_hz))
        .collect();
    let mut cases = Vec::new();
    for &i in &loaded {
        let gi = interface_rows(body, i);
        let held: Vec<usize> = interfaces.iter().copied().filter(|&n| n != i).collect();
        let nc = 6 * held.len();
        // Saddle-point system [[K, C^T], [C, 0]] with K = diag(0 (rigid), omega^2).
        let lu = if held.is_empty() {
            None
        } else {
            let nz = 6 + nm;
            let mut a = DMatrix::zeros(nz + nc, nz + nc);
            for (k, m) in body.modes.iter().enumerate() {
                a[(6 + k, 6 + k)] = m.stiffness;
            }
            for (h, &n) in held.iter().enumerate() {
                let gh = interface_rows(body, n);
                a.view_mut((nz + 6 * h, 0), (6, nz)).copy_from(&gh);
                a.view_mut((0, nz + 6 * h), (nz, 6))
                    .copy_from(&gh.transpose());
            }
            Some(a.lu())
        };
        let directions: Vec<usize> = match rule.load_n {
            Some(_) => vec![6],
            None if rule.load_moments => (0..6).collect(),
            None => (0..3).collect(),
        };
        for d in directions {
            let g: DVector<f64> = match rule.load_n {
                Some(w) => (0..3).map(|c| gi.row(c).transpose() * w[c]).sum(),
                None => gi.row(d).transpose(),
            };
            let p: Vec<f64> = match &lu {
                None => (0..nm).map(|k| g[6 + k]).collect(),
                Some(lu) => {
                    let mut rhs = DVector::zeros(6 + nm + nc);
                    rhs.rows_mut(0, 6 + nm).copy_from(&g);
                    let z = lu.solve(&rhs).ok_or_else(|| {
                        FlexError::Numerics(
                            "the interface nodes held do not hold the body (singular \
                             load-path system)"
                                .to_string(),
                        )
                    })?;
                    (0..nm)
                        .map(|k| body.modes[k].stiffness * z[6 + k])
                        .collect()
                }
            };
            let e: Vec<f64> = (0..nm)
                .map(|k| (amp[k] * p[k]).powi(2) / body.modes[k].stiffness)
                .collect();
            let total: f64 = e.iter().sum();
            let shares = e
                .iter()
                .map(|x| if total > 0.0 { x / total } else { 0.0 })
                .collect();
            cases.push(LoadCase {
                interface: body.nodes[i].name.clone(),
                direction: d,
                shares,
            });
        }
    }
    Ok(cases)
}

/// Applies `rule` to `body`'s modes.
pub fn select(body: &ModalData, rule: &Rule) -> Result<Selection, FlexError> {
    let nm = body.modes.len();
    match rule {
        Rule::All => Ok(Selection {
            selected: vec![true; nm],
            max_share: None,
            cases: vec![],
        }),
        Rule::Cutoff { max_hz } => Ok(Selection {
            selected: body
                .modes
                .iter()
                .map(|m| m.frequency_hz <= *max_hz)
                .collect(),
            max_share: None,
            cases: vec![],
        }),
        Rule::List { modes } => {
            for n in modes {
                if !body.modes.iter().any(|m| m.number == *n) {
                    let (a, b) = (
                        body.modes.first().map_or(0, |m| m.number),
                        body.modes.last().map_or(0, |m| m.number),
                    );
                    return Err(FlexError::Selection(format!(
                        "mode {n} is not an elastic mode of the table ({a}..{b})"
                    )));
                }
            }
            Ok(Selection {
                selected: body
                    .modes
                    .iter()
                    .map(|m| modes.contains(&m.number))
                    .collect(),
                max_share: None,
                cases: vec![],
            })
        }
        Rule::LoadPath(lp) => {
            let cases = load_path_cases(body, lp)?;
            let max_share: Vec<f64> = (0..nm)
                .map(|k| cases.iter().map(|c| c.shares[k]).fold(0.0, f64::max))
                .collect();
            Ok(Selection {
                selected: max_share
                    .iter()
                    .map(|&s| s >= lp.min_energy_share)
                    .collect(),
                max_share: Some(max_share),
                cases,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn amplification_is_the_sdof_peak_or_band_edge() {
        // Band below the mode: edge value 1 / (1 - r^2) for small damping.
        let a = band_amplification(317.0, 0.1, [0.0, 100.0]);
        let r: f64 = 100.0 / 317.0;
        let want = 1.0 / ((1.0 - r * r).powi(2) + (0.2 * r).powi(2)).sqrt();
        assert!((a - want).abs() < 1e-12);
        // Resonance inside the band: 1 / (2 zeta sqrt(1 - zeta^2)).
        let a = band_amplification(50.0, 0.01, [0.0, 100.0]);
        assert!((a - 1.0 / (0.02 * (1.0f64 - 1e-4).sqrt())).abs() < 1e-9);
    }
}
