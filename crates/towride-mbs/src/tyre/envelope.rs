//! Tandem-cam enveloping: the effective road a tyre feels on short obstacles.
//!
//! After Schmeitz (PhD thesis, TU Delft 2004) and Pacejka, "Tire and Vehicle Dynamics"
//! (3rd ed. 2012) sec. 10.2: two cams with a super-ellipse contour
//! (x/a_e)^c_e + (z/b_e)^c_e = 1 stand l_s apart along the wheel's heading and slide
//! vertically over the road, each resting on it at its highest contact. The lowest point of
//! a cam then lies at w = max over xi of [h(s + xi) + b_e (1 - |xi/a_e|^c_e)^(1/c_e)] - b_e.
//! The effective height is the mean of the front and rear cam, the effective forward slope
//! tan(beta) = (w_front - w_rear) / l_s. Several tandems side by side across the tread
//! width (ELLIPS_NWIDTH) are averaged. The effective curvature is the rate of change of the
//! effective slope along the road, d tan(beta)/ds / (1 + tan^2 beta)^(3/2).
//!
//! The maximisation is exact: the road reports where it has kinks or jumps along the line
//! ([`Road::kinks_along`]); between them the road is linear or concave and the cam contour
//! is concave (c_e >= 1), so the sum is concave: on a linear piece its maximum is where the
//! contour's slope cancels the road's (closed form), on a curved one a golden-section
//! search finds it, while kinks are evaluated directly (with the higher of the two one-sided road
//! heights at a jump). The result is therefore continuous in the wheel position, without
//! the stair-steps of a sampled road. Derivatives come from the envelope theorem,
//! dw/ds = -z_c'(xi*) at the maximiser xi*, so the slope rate needs no differencing.
//! Only the part of the cam within ELLIPS_MAX_STEP of its lowest point is searched (higher
//! parts cannot touch an obstacle lower than that).
//!
//! On a two-track profile (and so the ISO 8608 random road) every piece is an exact
//! quadratic along the cam's line, and `envelope_pieces.rs` finds each piece's maximum
//! without a search (and skips pieces that cannot hold it); other roads take the search
//! below.

use crate::road::Road;

use super::params::TyreParams;

/// The effective road plane under a tyre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EffectiveRoad {
    /// Effective height w [m].
    pub height: f64,
    /// Effective forward slope tan(beta) (positive uphill along the heading).
    pub tan_slope: f64,
    /// dw/ds and d tan(beta)/ds along the heading [1], [1/m].
    pub dheight_ds: f64,
    /// d tan(beta)/ds along the heading [1/m].
    pub dtan_ds: f64,
    /// Effective curvature [1/m].
    pub curvature: f64,
    /// True when every cam rested on a flat road (no enveloping work was done).
    pub flat: bool,
}

/// The cam geometry of one tyre.
#[derive(Clone, Debug)]
pub struct TandemCams {
    /// Cam semi-axis a_e along the heading [m].
    pub a: f64,
    /// Cam semi-axis b_e, vertical [m].
    pub b: f64,
    /// Cam contour exponent c_e (>= 1).
    pub c: f64,
    /// Tandem base l_s: distance between the front and rear cam [m].
    pub l_s: f64,
    /// Half length of the searched part of the cam [m].
    pub xi_max: f64,
    /// Lateral offsets of the tandems from the wheel centre plane [m].
    pub offsets: Vec<f64>,
    /// z_c at BOUND_INTERVALS + 1 points evenly over [0, xi_max] (envelope_pieces.rs).
    pub(super) bound: Vec<f64>,
    /// The last query and its answer: a Newton matrix built by finite differences asks
    /// for the same contact point again and again while it perturbs velocities and
    /// states, and the search over an obstacle is the tyre's costliest part.
    last: Box<LastQuery>,
}

/// A one-entry memo of [`TandemCams::effective`], keyed by the road's address and the
/// query; a clone starts empty (it may serve another road).
#[derive(Debug, Default)]
struct LastQuery(
    std::cell::Cell<Option<(usize, [f64; 6], EffectiveRoad)>>,
    /// Queries, memo hits, queries answered by the flat-road test alone.
    std::cell::Cell<[u64; 3]>,
);

impl Clone for LastQuery {
    fn clone(&self) -> Self {
        LastQuery::default()
    }
}

/// Tolerance of the golden-section search on the cam position [m].
const XI_TOL: f64 = 1e-10;

/// Largest departure of a road piece from its chord for which it counts as linear [m].
const LINEAR_TOL: f64 = 1e-12;

impl TandemCams {
    /// The cam geometry of a tyre with parameters `p`.
    pub fn new(p: &TyreParams) -> TandemCams {
        let (a, b, c) = (p.d.a_e, p.d.b_e, p.d.c_e);
        let step = p.ellips_max_step.min(b);
        // Solve b - z_c(xi) = step for |xi|.
        let u = (1.0 - (1.0 - step / b).powf(c)).max(0.0).powf(1.0 / c);
        let n = p.ellips_nwidth;
        let offsets = (0..n)
            .map(|i| p.width * ((i as f64 + 0.5) / n as f64 - 0.5))
            .collect();
        let mut cams = TandemCams {
            a,
            b,
            c,
            l_s: p.d.l_s,
            xi_max: a * u,
            offsets,
            bound: Vec::new(),
            last: Box::default(),
        };
        cams.fill_bound();
        cams
    }

    fn fill_bound(&mut self) {
        let n = super::envelope_pieces::BOUND_INTERVALS;
        self.bound = (0..=n)
            .map(|j| self.contour(self.xi_max * j as f64 / n as f64))
            .collect();
    }

    /// Effective-road queries so far: (all, answered from the memo, answered by the
    /// flat-road test without a search).
    pub fn query_counts(&self) -> [u64; 3] {
        self.last.1.get()
    }

    /// Height of the cam contour above the cam centre's lowest point plus b: z_c(xi).
    pub fn contour(&self, xi: f64) -> f64 {
        let u = (xi.abs() / self.a).min(1.0);
        self.b * (1.0 - u.powf(self.c)).max(0.0).powf(1.0 / self.c)
    }

    /// dz_c/dxi.
    pub fn contour_slope(&self, xi: f64) -> f64 {
        let u = (xi.abs() / self.a).min(1.0 - 1e-12);
        if u == 0.0 {
            return if self.c > 1.0 {
                0.0
            } else {
                -self.b / self.a * xi.signum()
            };
        }
        -(self.b / self.a)
            * xi.signum()
            * u.powf(self.c - 1.0)
            * (1.0 - u.powf(self.c)).powf(1.0 / self.c - 1.0)
    }

    /// Maximum of h(eta) + z_c(eta - s) over a piece [lo, hi] on which the road is linear,
    /// in closed form: the contour's slope equals minus the road's, z_c'(xi) = -m, at
    /// xi = sgn(m) a r / (1 + r^c)^(1/c) with r = (|m| a / b)^(1/(c-1)); the sum is concave,
    /// so the maximiser clamped to the piece is the piece's maximum. `None` when the piece
    /// is curved or the contour is not strictly convex (c <= 1): the caller searches.
    fn linear_piece_max(
        &self,
        h_at: &impl Fn(f64) -> f64,
        s: f64,
        lo: f64,
        hi: f64,
    ) -> Option<(f64, f64)> {
        if self.c <= 1.0 {
            return None;
        }
        // Interior points only: the ends may sit on a jump. A concave piece that meets
        // its chord at the midpoint is linear (pieces are smooth: lines or arcs).
        let len = hi - lo;
        let (q1, q3) = (lo + 0.25 * len, lo + 0.75 * len);
        let (h1, hm, h3) = (h_at(q1), h_at(lo + 0.5 * len), h_at(q3));
        if (hm - 0.5 * (h1 + h3)).abs() > LINEAR_TOL {
            return None;
        }
        let m = (h3 - h1) / (q3 - q1);
        let xi = if m == 0.0 {
            0.0
        } else {
            let r = (m.abs() * self.a / self.b).powf(1.0 / (self.c - 1.0));
            m.signum() * self.a * r / (1.0 + r.powf(self.c)).powf(1.0 / self.c)
        };
        let eta = (s + xi).clamp(lo, hi);
        Some((eta, h1 + m * (eta - q1) + self.contour(eta - s)))
    }

    /// Lowest point w of one cam centred at p + s d, and dw/ds.
    pub fn cam(
        &self,
        road: &Road,
        p: [f64; 2],
        d: [f64; 2],
        s: f64,
        kinks: &mut Vec<f64>,
    ) -> (f64, f64, bool) {
        self.cam_with(road, p, d, s, kinks, &mut Vec::new())
    }

    /// [`TandemCams::cam`] with a buffer for the road's pieces.
    fn cam_with(
        &self,
        road: &Road,
        p: [f64; 2],
        d: [f64; 2],
        s: f64,
        kinks: &mut Vec<f64>,
        pieces: &mut Vec<crate::road::Piece>,
    ) -> (f64, f64, bool) {
        let (s0, s1) = (s - self.xi_max, s + self.xi_max);
        let (xa, xb) = (p[0] + s0 * d[0], p[0] + s1 * d[0]);
        let (ya, yb) = (p[1] + s0 * d[1], p[1] + s1 * d[1]);
        if let Some(h) = road.flat_height(xa.min(xb), xa.max(xb), ya.min(yb), ya.max(yb)) {
            return (h, 0.0, true);
        }
        // Profile roads: exact quadratic pieces, no search (envelope_pieces.rs).
        if let Some((w, dw)) = self.cam_on_pieces(road, p, d, s, kinks, pieces) {
            return (w, dw, false);
        }
        let h_at = |eta: f64| road.height(p[0] + eta * d[0], p[1] + eta * d[1]);
        let g = |eta: f64| h_at(eta) + self.contour(eta - s);
        kinks.clear();
        road.kinks_along(p, d, s0, s1, kinks);
        // Candidates: window ends and kinks (upper one-sided limit at a jump).
        let mut best_eta = s0;
        let mut best = g(s0);
        let consider = |eta: f64, v: f64, best: &mut f64, best_eta: &mut f64| {
            if v > *best {
                *best = v;
                *best_eta = eta;
            }
        };
        let v1 = g(s1);
        consider(s1, v1, &mut best, &mut best_eta);
        for &k in kinks.iter() {
            let left = h_at(k - 1e-9).max(h_at(k));
            consider(k, left + self.contour(k - s), &mut best, &mut best_eta);
        }
        // Golden-section search on each smooth piece.
        let mut lo = s0;
        let mut pieces: Vec<f64> = kinks.clone();
        pieces.push(s1);
        for &hi in &pieces {
            if hi - lo > 2.0 * XI_TOL {
                let (eta, v) = self
                    .linear_piece_max(&h_at, s, lo, hi)
                    .unwrap_or_else(|| golden_max(&g, lo, hi));
                consider(eta, v, &mut best, &mut best_eta);
            }
            lo = hi;
        }
        let w = best - self.b;
        let xi = best_eta - s;
        let dw = if (best_eta - s0).abs() < XI_TOL || (best_eta - s1).abs() < XI_TOL {
            // The maximum sits on the window's edge, which moves with the cam.
            let (gx, gy) = road.slope(p[0] + best_eta * d[0], p[1] + best_eta * d[1]);
            gx * d[0] + gy * d[1]
        } else {
            -self.contour_slope(xi)
        };
        (w, dw, false)
    }

    /// The effective road under a wheel whose centre projects to `centre` (x, y), heading
    /// along the unit vector `heading` and with the lateral unit vector `lateral`.
    pub fn effective(
        &self,
        road: &Road,
        centre: [f64; 2],
        heading: [f64; 2],
        lateral: [f64; 2],
    ) -> EffectiveRoad {
        let key = (
            road as *const Road as usize,
            [
                centre[0], centre[1], heading[0], heading[1], lateral[0], lateral[1],
            ],
        );
        let mut st = self.last.1.get();
        st[0] += 1;
        if let Some((r, q, e)) = self.last.0.get() {
            if (r, q) == key {
                st[1] += 1;
                self.last.1.set(st);
                return e;
            }
        }
        let e = self.effective_uncached(road, centre, heading, lateral);
        st[2] += u64::from(e.flat);
        self.last.1.set(st);
        self.last.0.set(Some((key.0, key.1, e)));
        e
    }

    fn effective_uncached(
        &self,
        road: &Road,
        centre: [f64; 2],
        heading: [f64; 2],
        lateral: [f64; 2],
    ) -> EffectiveRoad {
        let (mut kinks, mut pieces) = (Vec::new(), Vec::new());
        let (mut w, mut tan, mut dw, mut dtan) = (0.0, 0.0, 0.0, 0.0);
        let mut flat = true;
        let n = self.offsets.len() as f64;
        for &y in &self.offsets {
            let p = [centre[0] + y * lateral[0], centre[1] + y * lateral[1]];
            let (wf, dwf, ff) =
                self.cam_with(road, p, heading, 0.5 * self.l_s, &mut kinks, &mut pieces);
            let (wr, dwr, fr) =
                self.cam_with(road, p, heading, -0.5 * self.l_s, &mut kinks, &mut pieces);
            flat &= ff && fr;
            w += 0.5 * (wf + wr) / n;
            tan += (wf - wr) / self.l_s / n;
            dw += 0.5 * (dwf + dwr) / n;
            dtan += (dwf - dwr) / self.l_s / n;
        }
        EffectiveRoad {
            height: w,
            tan_slope: tan,
            dheight_ds: dw,
            dtan_ds: dtan,
            curvature: dtan / (1.0 + tan * tan).powf(1.5),
            flat,
        }
    }
}

/// Maximum of a concave (unimodal) function on [lo, hi] by golden-section search.
pub(super) fn golden_max(f: &impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> (f64, f64) {
    const R: f64 = 0.618_033_988_749_895;
    let mut x1 = hi - R * (hi - lo);
    let mut x2 = lo + R * (hi - lo);
    let mut f1 = f(x1);
    let mut f2 = f(x2);
    while hi - lo > XI_TOL {
        if f1 < f2 {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + R * (hi - lo);
            f2 = f(x2);
        } else {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - R * (hi - lo);
            f1 = f(x1);
        }
    }
    if f1 > f2 {
        (x1, f1)
    } else {
        (x2, f2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form maximiser on a linear piece against a golden-section search of the
    /// same function, for flat, gentle, steep and clamped cases on both sides.
    #[test]
    fn closed_form_matches_search_on_linear_pieces() {
        let cams = TandemCams {
            a: 0.2,
            b: 0.18,
            c: 1.8,
            l_s: 0.15,
            xi_max: 0.12,
            offsets: vec![0.0],
            bound: Vec::new(),
            last: Box::default(),
        };
        for m in [0.0, 0.05, -0.3, 1.0, -1.0, 4.0] {
            for (lo, hi) in [(-0.12, 0.12), (0.02, 0.1), (-0.1, -0.03)] {
                let h = |eta: f64| 0.01 + m * eta;
                let g = |eta: f64| h(eta) + cams.contour(eta - 0.01);
                let (e1, v1) = cams.linear_piece_max(&h, 0.01, lo, hi).unwrap();
                let (e2, v2) = golden_max(&g, lo, hi);
                // The search stops within XI_TOL of a clamped maximiser, where the sum
                // still has a slope: the closed form is never lower, and higher by at most
                // that slope times XI_TOL.
                assert!(v1 >= v2 - 1e-15 && v1 - v2 < 1e-9, "m {m}: {v1} vs {v2}");
                assert!((e1 - e2).abs() < 1e-6, "m {m}: at {e1} vs {e2}");
            }
        }
        // A curved piece is left to the search.
        let arc = |eta: f64| (0.25 - eta * eta).sqrt();
        assert!(cams.linear_piece_max(&arc, 0.0, -0.1, 0.1).is_none());
    }
}
