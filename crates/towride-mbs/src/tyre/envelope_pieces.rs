//! The cam maximum on a road made of polynomial pieces (two-track profiles and the ISO 8608
//! random road), without a search.
//!
//! Along the cam's line such a road is, between its kinks, an exact quadratic
//! h(eta) = h_m + h'_m u + c2 u^2 (u = eta - mid; [`crate::road::Piece`]): each track is
//! linear between its samples and the blend across the tracks is linear in y, so a heading
//! with a lateral component makes the product quadratic. The general search
//! ([`TandemCams::cam`]) then finds no linear piece and runs a golden-section search on
//! every piece (about 50 height queries each); on a profile sampled every 5 cm that search
//! was 57 % of a class C run's time (perf; docs/roads.md, "Cost on a dense profile").
//!
//! Here each piece's maximum of g(eta) = h(eta) + z_c(eta - s) comes from the stationarity
//! condition z_c'(xi) = -h'(eta), xi = eta - s, solved by the fixed-point iteration
//! eta <- clamp(s + xi*(h'(eta))) with xi*(m) the closed-form root for a constant slope m
//! (see `linear_piece_max`). For 1 < c_e <= 2 the contour's curvature is bounded away from
//! zero: z_c''(xi) = -(c-1) (b/a^2) u^(c-2) (1-u^c)^(1/c-2) with u = |xi|/a, both factors
//! at least 1, so |z_c''| >= (c-1) b/a^2 and |dxi*/dm| = 1/|z_c''| <= a^2/((c-1) b). The map is
//! then a contraction with factor k = 2 |c2| a^2 / ((c-1) b) (clamping does not enlarge
//! it), and g is concave when k < 1, so its fixed point is the piece's maximum (at an end
//! when the clamp is active, as for a concave function). c2 is the heading's lateral
//! component times the difference of the tracks' slopes over the track width, so k is
//! tiny for the small yaw of a straight run. Where k > 1/2 or c_e > 2 (z_c'' vanishes at
//! xi = 0) the piece falls back to the golden-section search, as before. A linear piece
//! (c2 = 0) needs one step. Pieces that cannot beat the best so far are skipped (the
//! bound in `cam_on_pieces`).

use crate::road::{Piece, Road};

use super::envelope::{golden_max, TandemCams};

/// Stop the fixed-point iteration when the cam position moves less than this [m].
const ETA_TOL: f64 = 1e-13;

/// Largest contraction factor for which the fixed-point iteration is used.
const K_MAX: f64 = 0.5;

/// Intervals of the contour table over [0, xi_max] (the bound used to skip pieces).
pub(super) const BOUND_INTERVALS: usize = 64;

impl TandemCams {
    /// An upper bound of z_c(xi) for |xi| >= dist: the table's value at the grid point at
    /// or inside dist (z_c falls with |xi|).
    fn contour_bound(&self, dist: f64) -> f64 {
        let j = (dist / self.xi_max * BOUND_INTERVALS as f64).floor();
        self.bound[(j.max(0.0) as usize).min(BOUND_INTERVALS)]
    }

    /// xi where the contour's slope is -m: z_c'(xi) = -m (c_e > 1).
    fn xi_for_slope(&self, m: f64) -> f64 {
        if m == 0.0 {
            return 0.0;
        }
        let r = (m.abs() * self.a / self.b).powf(1.0 / (self.c - 1.0));
        m.signum() * self.a * r / (1.0 + r.powf(self.c)).powf(1.0 / self.c)
    }

    /// Maximum (eta, g) of g(eta) = h(eta) + z_c(eta - s) on one piece.
    fn piece_max(&self, pc: &Piece, s: f64) -> (f64, f64) {
        let g = |eta: f64| pc.height(eta) + self.contour(eta - s);
        let k = if self.c > 1.0 && self.c <= 2.0 {
            2.0 * pc.c2.abs() * self.a * self.a / ((self.c - 1.0) * self.b)
        } else {
            f64::INFINITY
        };
        if (k > K_MAX && pc.c2 != 0.0) || self.c <= 1.0 {
            return golden_max(&g, pc.lo, pc.hi);
        }
        let step = |eta: f64| (s + self.xi_for_slope(pc.slope(eta))).clamp(pc.lo, pc.hi);
        let mut eta = step(pc.mid);
        if pc.c2 != 0.0 {
            // Error after a step <= k / (1 - k) times the step (contraction).
            for _ in 0..60 {
                let next = step(eta);
                let moved = (next - eta).abs();
                eta = next;
                if moved <= ETA_TOL {
                    break;
                }
            }
        }
        (eta, g(eta))
    }

    /// [`TandemCams::cam`] on a road of polynomial pieces: `None` when the road has none
    /// (the caller searches). Same result: the lowest point w of the cam centred at
    /// p + s d and dw/ds by the envelope theorem.
    pub(super) fn cam_on_pieces(
        &self,
        road: &Road,
        p: [f64; 2],
        d: [f64; 2],
        s: f64,
        kinks: &mut Vec<f64>,
        pieces: &mut Vec<Piece>,
    ) -> Option<(f64, f64)> {
        let (s0, s1) = (s - self.xi_max, s + self.xi_max);
        if !road.pieces_along(p, d, s0, s1, kinks, pieces) {
            return None;
        }
        // Each piece's maximum over its closed interval covers the window ends and both
        // one-sided heights at a kink. The piece under the cam's centre goes first; a
        // piece whose upper bound (its highest end, plus the most a concave quadratic
        // rises above its chord, |c2| len^2 / 4, plus the contour's value at the piece's
        // nearest point from the table) is below the best so far cannot hold the maximum.
        let first = pieces.iter().position(|pc| pc.hi >= s).unwrap_or(0);
        let order = std::iter::once(first).chain((0..pieces.len()).filter(|&i| i != first));
        let mut best: Option<(f64, f64, usize)> = None;
        for i in order {
            let pc = &pieces[i];
            if let Some((_, b, _)) = best {
                let half = 0.5 * (pc.hi - pc.lo);
                let rise = (-pc.c2).max(0.0) * half * half;
                let dist = (pc.lo - s).max(s - pc.hi).max(0.0);
                let ub = pc.height(pc.lo).max(pc.height(pc.hi)) + rise + self.contour_bound(dist);
                // 1e-15 m: rounding of the bound's terms.
                if ub + 1e-15 < b {
                    continue;
                }
            }
            let (eta, v) = self.piece_max(pc, s);
            if best.is_none_or(|(_, b, _)| v > b) {
                best = Some((eta, v, i));
            }
        }
        let (eta, v, i) = best?;
        let at_edge = (eta - s0).abs() < 1e-10 || (eta - s1).abs() < 1e-10;
        // On the window's edge the maximum moves with the cam (the road's slope there);
        // elsewhere the envelope theorem gives -z_c'(xi).
        let dw = if at_edge {
            pieces[i].slope(eta)
        } else {
            -self.contour_slope(eta - s)
        };
        Some((v - self.b, dw))
    }
}
