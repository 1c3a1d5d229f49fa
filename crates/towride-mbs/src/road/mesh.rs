//! A 3D road: heights on a regular (x, y) grid, triangulated and queried through
//! `parry3d-f64` (a [`TriMesh`] with its bounding-volume tree; heights by a vertical ray
//! cast, slopes from the hit triangle's normal).
//!
//! The CSV has a header `x_m,y_m,z_m` and one row per grid node (any order); the nodes must
//! fill a full rectangular grid. Each grid cell is split into two triangles along the
//! diagonal from (x_i, y_j) to (x_i+1, y_j+1). Outside the grid the height is that of the
//! nearest point of the grid's border.

use super::RoadError;
use std::path::{Path, PathBuf};

use parry3d_f64::math::{Point, Vector};
use parry3d_f64::query::{Ray, RayCast};
use parry3d_f64::shape::TriMesh;

use crate::input::InputError;

use super::{push_x_crossing, push_y_crossing};

/// A triangulated height field.
#[derive(Clone)]
pub struct HeightField {
    /// The file the height field was read from.
    pub file: PathBuf,
    xs: Vec<f64>,
    ys: Vec<f64>,
    /// Heights, row-major by y: z[j * nx + i] at (xs[i], ys[j]).
    z: Vec<f64>,
    /// Per cell: Some(z) when all four corners share the height z.
    cell_flat: Vec<Option<f64>>,
    mesh: TriMesh,
    z_top: f64,
}

impl std::fmt::Debug for HeightField {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "HeightField({} x {} nodes)",
            self.xs.len(),
            self.ys.len()
        )
    }
}

impl HeightField {
    /// Builds the field from grid coordinates and heights z[j * nx + i].
    pub fn new(xs: Vec<f64>, ys: Vec<f64>, z: Vec<f64>) -> Result<HeightField, RoadError> {
        let (nx, ny) = (xs.len(), ys.len());
        if nx < 2 || ny < 2 {
            return Err(RoadError::Geometry(format!(
                "a height field needs at least 2 x 2 nodes, got {nx} x {ny}"
            )));
        }
        if z.len() != nx * ny {
            return Err(RoadError::Geometry(format!(
                "{} heights for a {nx} x {ny} grid",
                z.len()
            )));
        }
        if xs
            .windows(2)
            .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
            || ys
                .windows(2)
                .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        {
            return Err(RoadError::Geometry(
                "grid coordinates must increase strictly".into(),
            ));
        }
        if let Some(v) = z.iter().find(|v| !v.is_finite()) {
            return Err(RoadError::Geometry(format!("height {v} is not finite")));
        }
        let verts: Vec<Point<f64>> = (0..ny)
            .flat_map(|j| (0..nx).map(move |i| (i, j)))
            .map(|(i, j)| Point::new(xs[i], ys[j], z[j * nx + i]))
            .collect();
        let mut tris = Vec::with_capacity(2 * (nx - 1) * (ny - 1));
        let mut cell_flat = Vec::with_capacity((nx - 1) * (ny - 1));
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let v00 = (j * nx + i) as u32;
                let v10 = v00 + 1;
                let v01 = v00 + nx as u32;
                let v11 = v01 + 1;
                // Counter-clockwise seen from above, so normals point up.
                tris.push([v00, v10, v11]);
                tris.push([v00, v11, v01]);
                let c = [v00, v10, v01, v11].map(|k| z[k as usize]);
                cell_flat.push(if c.iter().all(|&h| h == c[0]) {
                    Some(c[0])
                } else {
                    None
                });
            }
        }
        let mesh = TriMesh::new(verts, tris)
            .map_err(|e| RoadError::Geometry(format!("triangle mesh: {e:?}")))?;
        let z_top = z.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        Ok(HeightField {
            file: PathBuf::new(),
            xs,
            ys,
            z,
            cell_flat,
            mesh,
            z_top,
        })
    }

    /// Reads the grid CSV (see the module docs); errors name the file and line.
    pub fn from_csv(file: &Path, loader: &crate::input::Loader) -> Result<HeightField, InputError> {
        let err = |line: Option<usize>, field: &str, msg: String| {
            crate::input::csv_table::error(file, line, field, msg)
        };
        let rows = crate::input::csv_table::read_columns(file, &["x_m", "y_m", "z_m"], loader)?;
        let pts: Vec<(f64, f64, f64, Option<usize>)> = rows
            .iter()
            .map(|r| (r.values[0], r.values[1], r.values[2], r.line))
            .collect();
        // Errors at a row an override changed are the override's.
        let err = |line: Option<usize>, field: &str, msg: String| {
            crate::input::csv_table::blamed(file, &rows, err(line, field, msg))
        };
        let uniq = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v.dedup();
            v
        };
        let xs = uniq(pts.iter().map(|p| p.0).collect());
        let ys = uniq(pts.iter().map(|p| p.1).collect());
        let (nx, ny) = (xs.len(), ys.len());
        if nx < 2 || ny < 2 {
            let last = pts.last().and_then(|p| p.3);
            return Err(err(
                last,
                if nx < 2 { "x_m" } else { "y_m" },
                format!("a height field needs at least 2 x 2 nodes, got {nx} x {ny}"),
            ));
        }
        let mut seen = std::collections::HashSet::new();
        for &(x, y, _, line) in &pts {
            if !seen.insert((x.to_bits(), y.to_bits())) {
                return Err(err(line, "x_m", format!("node ({x}, {y}) given twice")));
            }
        }
        if pts.len() != nx * ny {
            // Name the row whose coordinate the fewest rows share: a typo makes a lone
            // value, a missing row leaves its column one short.
            let mut counts = std::collections::HashMap::new();
            for p in &pts {
                *counts.entry((0, p.0.to_bits())).or_insert(0usize) += 1;
                *counts.entry((1, p.1.to_bits())).or_insert(0usize) += 1;
            }
            let (line, field, v, n) = pts
                .iter()
                .flat_map(|p| [(p.3, 0, p.0), (p.3, 1, p.1)])
                .map(|(l, c, v)| (l, c, v, counts[&(c, v.to_bits())]))
                .min_by_key(|t| t.3)
                .map(|(l, c, v, n)| (l, ["x_m", "y_m"][c], v, n))
                .unwrap_or((None, "", 0.0, 0));
            return Err(err(
                line,
                field,
                format!(
                    "{} rows do not fill the {nx} x {ny} grid of their coordinates: \
                     {field} = {v} is shared by {n} row(s) only",
                    pts.len()
                ),
            ));
        }
        let mut z = vec![f64::NAN; nx * ny];
        for &(x, y, h, line) in &pts {
            let i = xs.partition_point(|&v| v < x);
            let j = ys.partition_point(|&v| v < y);
            let k = j * nx + i;
            if !z[k].is_nan() {
                return Err(err(line, "x_m", format!("node ({x}, {y}) given twice")));
            }
            z[k] = h;
        }
        let mut f = HeightField::new(xs, ys, z).map_err(|m| err(None, "", m.to_string()))?;
        f.file = file.to_path_buf();
        Ok(f)
    }

    fn clamp_xy(&self, x: f64, y: f64) -> (f64, f64) {
        let (nx, ny) = (self.xs.len(), self.ys.len());
        (
            x.clamp(self.xs[0], self.xs[nx - 1]),
            y.clamp(self.ys[0], self.ys[ny - 1]),
        )
    }

    /// Vertical ray cast onto the mesh: height and upward normal.
    fn cast(&self, x: f64, y: f64) -> (f64, Vector<f64>) {
        let (x, y) = self.clamp_xy(x, y);
        let start = self.z_top + 1.0;
        let ray = Ray::new(Point::new(x, y, start), Vector::new(0.0, 0.0, -1.0));
        match self
            .mesh
            .cast_local_ray_and_get_normal(&ray, f64::MAX, false)
        {
            Some(hit) => {
                let n = if hit.normal.z < 0.0 {
                    -hit.normal
                } else {
                    hit.normal
                };
                (start - hit.time_of_impact, n)
            }
            // Only on the very border can floating point miss the mesh: use the bilinear
            // value of the cell instead.
            None => (self.bilinear(x, y), Vector::new(0.0, 0.0, 1.0)),
        }
    }

    fn cell(&self, x: f64, y: f64) -> (usize, usize) {
        let i = self
            .xs
            .partition_point(|&v| v <= x)
            .clamp(1, self.xs.len() - 1)
            - 1;
        let j = self
            .ys
            .partition_point(|&v| v <= y)
            .clamp(1, self.ys.len() - 1)
            - 1;
        (i, j)
    }

    fn bilinear(&self, x: f64, y: f64) -> f64 {
        let (i, j) = self.cell(x, y);
        let nx = self.xs.len();
        let u = (x - self.xs[i]) / (self.xs[i + 1] - self.xs[i]);
        let v = (y - self.ys[j]) / (self.ys[j + 1] - self.ys[j]);
        let z = |a: usize, b: usize| self.z[(j + b) * nx + i + a];
        (1.0 - u) * (1.0 - v) * z(0, 0)
            + u * (1.0 - v) * z(1, 0)
            + (1.0 - u) * v * z(0, 1)
            + u * v * z(1, 1)
    }

    /// Road height z [m] at (x, y), bilinear in each cell.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        self.cast(x, y).0
    }

    /// Surface gradient (dz/dx, dz/dy) at (x, y); zero outside the grid.
    pub fn slope(&self, x: f64, y: f64) -> (f64, f64) {
        let inside = x > self.xs[0]
            && x < self.xs[self.xs.len() - 1]
            && y > self.ys[0]
            && y < self.ys[self.ys.len() - 1];
        if !inside {
            // The border extension is constant along the outward direction; keep it simple.
            return (0.0, 0.0);
        }
        let (_, n) = self.cast(x, y);
        (-n.x / n.z, -n.y / n.z)
    }

    /// `Some(z)` when every cell touching [x0, x1] x [y0, y1] is flat at height z.
    pub fn flat_height(&self, x0: f64, x1: f64, y0: f64, y1: f64) -> Option<f64> {
        let (i0, j0) = self.cell(x0, y0);
        let (i1, j1) = self.cell(x1, y1);
        let nxc = self.xs.len() - 1;
        let mut z = None;
        for j in j0..=j1 {
            for i in i0..=i1 {
                let c = self.cell_flat[j * nxc + i]?;
                match z {
                    None => z = Some(c),
                    Some(h) if h != c => return None,
                    _ => {}
                }
            }
        }
        z
    }

    /// Appends to `out` the parameters s in [s0, s1] where the line p + s d crosses a grid
    /// line or a cell diagonal (the kinks of the triangulated surface).
    pub fn kinks_along(&self, p: [f64; 2], d: [f64; 2], s0: f64, s1: f64, out: &mut Vec<f64>) {
        let from = out.len();
        for &x in &self.xs {
            push_x_crossing(p, d, x, s0, s1, out);
        }
        for &y in &self.ys {
            push_y_crossing(p, d, y, s0, s1, out);
        }
        // Diagonal crossings, one per cell the line passes through.
        let mut grid: Vec<f64> = out[from..].to_vec();
        grid.push(s0);
        grid.push(s1);
        grid.sort_by(f64::total_cmp);
        for w in grid.windows(2) {
            if w[1] - w[0] < 1e-12 {
                continue;
            }
            let sm = 0.5 * (w[0] + w[1]);
            let (xm, ym) = (p[0] + sm * d[0], p[1] + sm * d[1]);
            let inside = xm > self.xs[0]
                && xm < self.xs[self.xs.len() - 1]
                && ym > self.ys[0]
                && ym < self.ys[self.ys.len() - 1];
            if !inside {
                continue;
            }
            let (i, j) = self.cell(xm, ym);
            let (dx, dy) = (self.xs[i + 1] - self.xs[i], self.ys[j + 1] - self.ys[j]);
            // p + s d = (x_i, y_j) + u (dx, dy): solve for s and u.
            let det = d[0] * (-dy) - d[1] * (-dx);
            if det.abs() < 1e-15 {
                continue;
            }
            let rx = self.xs[i] - p[0];
            let ry = self.ys[j] - p[1];
            let s = (rx * (-dy) - ry * (-dx)) / det;
            if s > w[0] && s < w[1] {
                out.push(s);
            }
        }
    }

    /// First and last x of the grid [m].
    pub fn x_range(&self) -> (f64, f64) {
        (self.xs[0], self.xs[self.xs.len() - 1])
    }

    /// A short description for logs and reports.
    pub fn describe(&self) -> String {
        format!(
            "height field {} ({} x {} nodes, x {:.2}..{:.2} m, y {:.2}..{:.2} m)",
            self.file.display(),
            self.xs.len(),
            self.ys.len(),
            self.xs[0],
            self.xs[self.xs.len() - 1],
            self.ys[0],
            self.ys[self.ys.len() - 1]
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plane z = 0.1 x + 0.05 y is reproduced exactly by any triangulation.
    #[test]
    fn plane_is_exact() {
        let xs: Vec<f64> = (0..6).map(|i| i as f64 * 0.5).collect();
        let ys: Vec<f64> = (0..4).map(|j| -1.0 + j as f64 * 0.7).collect();
        let mut z = Vec::new();
        for &y in &ys {
            for &x in &xs {
                z.push(0.1 * x + 0.05 * y);
            }
        }
        let f = HeightField::new(xs, ys, z).unwrap();
        for &(x, y) in &[(0.3, -0.2), (1.77, 0.9), (2.2, -0.95)] {
            assert!((f.height(x, y) - (0.1 * x + 0.05 * y)).abs() < 1e-12);
            let (sx, sy) = f.slope(x, y);
            assert!((sx - 0.1).abs() < 1e-12 && (sy - 0.05).abs() < 1e-12);
        }
        assert_eq!(f.flat_height(0.1, 0.2, 0.0, 0.1), None);
    }
}
