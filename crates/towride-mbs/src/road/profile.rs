//! A longitudinal road profile per track, read from CSV.
//!
//! The CSV has a header `x_m,z_left_m,z_right_m` and one row per point, x strictly
//! increasing. The left track runs at y = +track_width/2, the right one at
//! y = -track_width/2; between them the height is blended linearly in y, outside them it is
//! the nearer track's. Between points the profile is linear; before the first and after the
//! last point it is `outside_height_m` if given, else the end value.

use super::RoadError;
use std::path::{Path, PathBuf};

use crate::input::InputError;

use super::{push_x_crossing, push_y_crossing};

/// One piece of a road along a line: h(s) = h + dh (s - mid) + c2 (s - mid)^2 on
/// [lo, hi] (one-sided at the ends where the road jumps).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// Start and end of the piece along the line [m].
    pub lo: f64,
    /// See `lo`.
    pub hi: f64,
    /// The expansion point (the piece's middle) [m].
    pub mid: f64,
    /// Height at `mid` [m].
    pub h: f64,
    /// dh/ds at `mid` [1].
    pub dh: f64,
    /// Half the second derivative d2h/ds2 [1/m].
    pub c2: f64,
}

impl Piece {
    /// Height at s [m].
    pub fn height(&self, s: f64) -> f64 {
        let u = s - self.mid;
        self.h + u * (self.dh + u * self.c2)
    }

    /// dh/ds at s [1].
    pub fn slope(&self, s: f64) -> f64 {
        self.dh + 2.0 * self.c2 * (s - self.mid)
    }
}

/// Two measured tracks.
#[derive(Clone, Debug)]
pub struct TrackProfile {
    /// The file the profile was read from.
    pub file: PathBuf,
    x: Vec<f64>,
    left: Vec<f64>,
    right: Vec<f64>,
    half_track: f64,
    outside: Option<f64>,
}

impl TrackProfile {
    /// Builds a profile from points; x must be strictly increasing.
    pub fn new(
        x: Vec<f64>,
        left: Vec<f64>,
        right: Vec<f64>,
        track_width: f64,
        outside: Option<f64>,
    ) -> Result<TrackProfile, RoadError> {
        if x.len() < 2 || left.len() != x.len() || right.len() != x.len() {
            return Err(RoadError::Geometry(
                "a profile needs at least two points with both tracks".into(),
            ));
        }
        if let Some(i) = (1..x.len()).find(|&i| x[i].is_nan() || x[i] <= x[i - 1]) {
            return Err(RoadError::Geometry(format!(
                "x must increase strictly (point {i})"
            )));
        }
        if track_width.is_nan() || track_width <= 0.0 {
            return Err(RoadError::Geometry(format!(
                "track width must be positive, got {track_width}"
            )));
        }
        Ok(TrackProfile {
            file: PathBuf::new(),
            x,
            left,
            right,
            half_track: track_width / 2.0,
            outside,
        })
    }

    /// Reads `file` (see the module docs); errors name the file and line.
    pub fn from_csv(
        file: &Path,
        track_width: f64,
        outside: Option<f64>,
        loader: &crate::input::Loader,
    ) -> Result<TrackProfile, InputError> {
        let err = |line: Option<usize>, field: &str, msg: String| {
            crate::input::csv_table::error(file, line, field, msg)
        };
        let rows =
            crate::input::csv_table::read_columns(file, &["x_m", "z_left_m", "z_right_m"], loader)?;
        let (mut x, mut l, mut r) = (Vec::new(), Vec::new(), Vec::new());
        for row in &rows {
            let line = row.line;
            let xi = row.values[0];
            if let Some(&prev) = x.last() {
                if xi <= prev {
                    let e = err(
                        line,
                        "x_m",
                        format!("must increase strictly ({xi} after {prev})"),
                    );
                    return Err(crate::input::csv_table::blamed(file, &rows, e));
                }
            }
            x.push(xi);
            l.push(row.values[1]);
            r.push(row.values[2]);
        }
        let mut p = TrackProfile::new(x, l, r, track_width, outside)
            .map_err(|m| err(None, "", m.to_string()))?;
        p.file = file.to_path_buf();
        Ok(p)
    }

    /// Height of one track (`v` = left or right values) at x, and its slope.
    fn track(&self, v: &[f64], x: f64) -> (f64, f64) {
        let n = self.x.len();
        if x < self.x[0] {
            return (self.outside.unwrap_or(v[0]), 0.0);
        }
        if x >= self.x[n - 1] {
            return (self.outside.unwrap_or(v[n - 1]), 0.0);
        }
        // Right-continuous: the interval [x_i, x_i+1) holding x.
        let i = self.x.partition_point(|&xi| xi <= x) - 1;
        let s = (v[i + 1] - v[i]) / (self.x[i + 1] - self.x[i]);
        (v[i] + s * (x - self.x[i]), s)
    }

    /// Blend weight of the left track at lateral position y, and its y-derivative.
    fn weight(&self, y: f64) -> (f64, f64) {
        let t = (y + self.half_track) / (2.0 * self.half_track);
        if t <= 0.0 {
            (0.0, 0.0)
        } else if t >= 1.0 {
            (1.0, 0.0)
        } else {
            (t, 1.0 / (2.0 * self.half_track))
        }
    }

    /// Road height z [m] at (x, y), interpolated between the two tracks.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let (t, _) = self.weight(y);
        let (zl, _) = self.track(&self.left, x);
        let (zr, _) = self.track(&self.right, x);
        t * zl + (1.0 - t) * zr
    }

    /// Surface gradient (dz/dx, dz/dy) at (x, y).
    pub fn slope(&self, x: f64, y: f64) -> (f64, f64) {
        let (t, dt) = self.weight(y);
        let (zl, sl) = self.track(&self.left, x);
        let (zr, sr) = self.track(&self.right, x);
        (t * sl + (1.0 - t) * sr, dt * (zl - zr))
    }

    /// `Some(z)` when both tracks in use are flat at height z over [x0, x1] x [y0, y1].
    pub fn flat_height(&self, x0: f64, x1: f64, y0: f64, y1: f64) -> Option<f64> {
        let (t0, _) = self.weight(y0);
        let (t1, _) = self.weight(y1);
        let mut tracks: Vec<&[f64]> = Vec::new();
        if t1 > 0.0 {
            tracks.push(&self.left);
        }
        if t0 < 1.0 {
            tracks.push(&self.right);
        }
        let z0 = self.height(x0, y0);
        // Every node in [x0, x1] and both ends must sit at z0 on every track in use.
        let i0 = self.x.partition_point(|&xi| xi < x0);
        let i1 = self.x.partition_point(|&xi| xi <= x1);
        for v in tracks {
            let (a, sa) = self.track(v, x0);
            let (b, _) = self.track(v, x1);
            if a != z0 || b != z0 || sa != 0.0 {
                return None;
            }
            if v[i0.min(v.len())..i1.min(v.len())].iter().any(|&z| z != z0) {
                return None;
            }
            // Ends beyond the data use the outside height; the data ends must match too.
            if x0 < self.x[0] && x1 >= self.x[0] && v[0] != z0 {
                return None;
            }
            let n = self.x.len();
            if x1 >= self.x[n - 1] && x0 < self.x[n - 1] && v[n - 1] != z0 {
                return None;
            }
        }
        Some(z0)
    }

    /// Appends to `out` the parameters s in [s0, s1] where the line p + s d crosses a
    /// profile node or a track line.
    pub fn kinks_along(&self, p: [f64; 2], d: [f64; 2], s0: f64, s1: f64, out: &mut Vec<f64>) {
        // Only the nodes inside the line's x-range matter.
        let xa = p[0] + s0 * d[0];
        let xb = p[0] + s1 * d[0];
        let (lo, hi) = (xa.min(xb), xa.max(xb));
        let i0 = self.x.partition_point(|&xi| xi < lo);
        let i1 = self.x.partition_point(|&xi| xi <= hi);
        for &xk in &self.x[i0..i1] {
            push_x_crossing(p, d, xk, s0, s1, out);
        }
        push_y_crossing(p, d, self.half_track, s0, s1, out);
        push_y_crossing(p, d, -self.half_track, s0, s1, out);
    }

    /// The road along the line p + s d between consecutive `kinks` (sorted, inside
    /// [s0, s1]) as exact quadratics in s, one per piece: inside a piece both tracks are
    /// linear in x and the blend weight is linear (or constant) in y, so their blend is a
    /// polynomial of degree two in s (degree one when the line runs along x).
    pub fn pieces_along(
        &self,
        p: [f64; 2],
        d: [f64; 2],
        s0: f64,
        s1: f64,
        kinks: &[f64],
        out: &mut Vec<Piece>,
    ) {
        out.clear();
        let mut lo = s0;
        for &hi in kinks.iter().chain(std::iter::once(&s1)) {
            let mid = 0.5 * (lo + hi);
            let (x, y) = (p[0] + mid * d[0], p[1] + mid * d[1]);
            // Mid-piece queries see the piece's own segment and weight regime.
            let (zl, sl) = self.track(&self.left, x);
            let (zr, sr) = self.track(&self.right, x);
            let (t, dt) = self.weight(y);
            let (gl, gr, gt) = (sl * d[0], sr * d[0], dt * d[1]);
            out.push(Piece {
                lo,
                hi,
                mid,
                h: t * zl + (1.0 - t) * zr,
                dh: t * gl + (1.0 - t) * gr + gt * (zl - zr),
                c2: gt * (gl - gr),
            });
            lo = hi;
        }
    }

    /// Lateral distance of the two tracks [m].
    pub fn track_width(&self) -> f64 {
        2.0 * self.half_track
    }

    /// First and last x of the data [m].
    pub fn x_range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// A short description for logs and reports.
    pub fn describe(&self) -> String {
        format!(
            "two-track profile {} ({} points, x {:.2}..{:.2} m, track {:.3} m)",
            self.file.display(),
            self.x.len(),
            self.x[0],
            self.x[self.x.len() - 1],
            2.0 * self.half_track
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tracks_blend_and_flatness() {
        let p = TrackProfile::new(
            vec![0.0, 1.0, 2.0, 3.0],
            vec![0.0, 0.0, 0.02, 0.0],
            vec![0.0, 0.0, 0.0, 0.0],
            1.4,
            None,
        )
        .unwrap();
        assert!((p.height(2.0, 0.7) - 0.02).abs() < 1e-15);
        assert!((p.height(2.0, 0.0) - 0.01).abs() < 1e-15);
        assert_eq!(p.height(2.0, -0.7), 0.0);
        assert_eq!(p.flat_height(0.0, 0.9, -1.0, 1.0), Some(0.0));
        assert_eq!(p.flat_height(0.0, 1.5, 0.5, 1.0), None);
        assert_eq!(p.flat_height(0.0, 2.5, -1.0, -0.8), Some(0.0));
    }
}
