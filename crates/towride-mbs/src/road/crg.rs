//! OpenCRG road files (ASAM OpenCRG 1.2, the "curved regular grid"), text forms only
//! (`LRFI`: 10 characters per value, `LDFI`: 20), straight reference line only.
//!
//! Format (ASAM OpenCRG user manual 1.2 and the example files of `asam-ev/OpenCRG`,
//! `crg-txt/`; read cross-checked with `pyopencrg` in `tests/mbs/road_crg.rs`): header
//! blocks `$NAME ... $`, `$CT` free comment text, `$ROAD_CRG` keywords
//! `KEY = value` (`REFERENCE_LINE_START_U` default 0, `REFERENCE_LINE_INCREMENT`,
//! `LONG_SECTION_V_RIGHT` / `_LEFT` / `_INCREMENT`; without `V_RIGHT` the sections are
//! centred on the reference line), `$KD_Definition` with the format `#:LRFI` and one
//! `D:long section i,m` line per channel; after `$$$$` one record per cross-section u,
//! each starting on a new line, `80 / width` values per line, `*missing*` for no data.
//! Channel 1 is the rightmost section (v = v_right), the last the leftmost.
//!
//! The road: u = x - x0 along the world x axis, v = y - y0 to the left; the height is
//! bilinear in the cell (as OpenCRG's evaluator); outside the grid the border value is kept.
//! Not supported (refused with the keyword named): curved, sloped or banked reference lines,
//! modifiers and options blocks, missing values, file references and the binary forms
//! (`KRBI`, `KDBI`).

use std::path::Path;

use super::{push_x_crossing, push_y_crossing};

/// A CRG elevation grid on a straight reference line along x.
#[derive(Clone, Debug)]
pub struct CrgGrid {
    /// u of the first cross-section (= x of the grid's start) [m].
    pub u0: f64,
    /// Spacing along u [m].
    pub du: f64,
    /// v of the rightmost long section [m].
    pub v0: f64,
    /// Spacing across [m].
    pub dv: f64,
    nu: usize,
    nv: usize,
    /// z[i * nv + j]: cross-section i, long section j (right to left) [m].
    z: Vec<f64>,
}

/// An error of a CRG file: its 1-based line and message.
pub type CrgError = (usize, String);

impl CrgGrid {
    /// Parses the text of a CRG file.
    pub fn parse(text: &str) -> Result<CrgGrid, CrgError> {
        let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
        let (mut section, mut width, mut channels) = (String::new(), 0usize, 0usize);
        let mut kv: Vec<(String, f64, usize)> = Vec::new();
        let mut data_line = 0;
        for (no, raw) in lines.by_ref() {
            let l = raw.trim_end();
            if l.starts_with("$$$$") {
                data_line = no;
                break;
            }
            if let Some(name) = l.strip_prefix('$') {
                section = name
                    .split_whitespace()
                    .next()
                    .unwrap_or("")
                    .to_ascii_uppercase();
                match section.as_str() {
                    "" | "CT" | "ROAD_CRG" | "KD_DEFINITION" => {}
                    other => return Err((no, format!("block ${other} is not supported"))),
                }
                continue;
            }
            if l.starts_with('*') || section == "CT" || l.trim().is_empty() {
                continue;
            }
            let body = l.split('!').next().unwrap_or("").trim();
            match section.as_str() {
                "ROAD_CRG" => {
                    let (k, v) = body
                        .split_once('=')
                        .ok_or((no, format!("expected KEY = value, got {body:?}")))?;
                    let k = k.trim().to_ascii_uppercase();
                    let v: f64 = v
                        .trim()
                        .parse()
                        .map_err(|_| (no, format!("{k}: not a number: {:?}", v.trim())))?;
                    kv.push((k, v, no));
                }
                "KD_DEFINITION" => {
                    if let Some(f) = body.strip_prefix("#:") {
                        width = match f.trim().to_ascii_uppercase().as_str() {
                            "LRFI" => 10,
                            "LDFI" => 20,
                            other => {
                                return Err((
                                    no,
                                    format!(
                                    "data format {other} is not supported (text LRFI or LDFI only)"
                                ),
                                ))
                            }
                        };
                    } else if let Some(d) = body.strip_prefix("D:") {
                        if !d.trim().to_ascii_lowercase().starts_with("long section") {
                            return Err((
                                no,
                                format!("channel {d:?} is not supported (long sections only)"),
                            ));
                        }
                        channels += 1;
                    } else if !body.starts_with('#') {
                        return Err((no, format!("unexpected line in $KD_Definition: {body:?}")));
                    }
                }
                _ => return Err((no, format!("line outside any block: {body:?}"))),
            }
        }
        if data_line == 0 {
            return Err((text.lines().count(), "no data block (a line $$$$)".into()));
        }
        if width == 0 || channels < 2 {
            return Err((
                data_line,
                "$KD_Definition needs a format (#:LRFI) and at least two long sections".into(),
            ));
        }
        let get = |k: &str| kv.iter().find(|e| e.0 == k).map(|e| (e.1, e.2));
        for (k, _, no) in &kv {
            match k.as_str() {
                "REFERENCE_LINE_START_U"
                | "REFERENCE_LINE_END_U"
                | "REFERENCE_LINE_INCREMENT"
                | "LONG_SECTION_V_RIGHT"
                | "LONG_SECTION_V_LEFT"
                | "LONG_SECTION_V_INCREMENT"
                | "REFERENCE_LINE_START_X"
                | "REFERENCE_LINE_START_Y" => {}
                "REFERENCE_LINE_START_PHI" if get(k).map(|g| g.0) == Some(0.0) => {}
                _ => {
                    return Err((
                        *no,
                        format!("{k} is not supported (straight reference line along x only)"),
                    ))
                }
            }
        }
        let (du, du_line) = get("REFERENCE_LINE_INCREMENT")
            .ok_or((data_line, "REFERENCE_LINE_INCREMENT is missing".to_string()))?;
        if !(du > 0.0 && du.is_finite()) {
            return Err((
                du_line,
                format!("REFERENCE_LINE_INCREMENT must be positive, got {du}"),
            ));
        }
        let nv = channels;
        let dv = match (
            get("LONG_SECTION_V_INCREMENT"),
            get("LONG_SECTION_V_RIGHT"),
            get("LONG_SECTION_V_LEFT"),
        ) {
            (Some((d, _)), _, _) => d,
            (None, Some((r, _)), Some((l, _))) => (l - r) / (nv - 1) as f64,
            _ => {
                return Err((
                    data_line,
                    "LONG_SECTION_V_INCREMENT (or V_RIGHT and V_LEFT) is missing".into(),
                ))
            }
        };
        if !(dv > 0.0 && dv.is_finite()) {
            return Err((
                data_line,
                format!("long section spacing must be positive, got {dv}"),
            ));
        }
        let v0 = get("LONG_SECTION_V_RIGHT").map_or(-dv * (nv - 1) as f64 / 2.0, |g| g.0)
            + get("REFERENCE_LINE_START_Y").map_or(0.0, |g| g.0);
        let u0 = get("REFERENCE_LINE_START_U").map_or(0.0, |g| g.0)
            + get("REFERENCE_LINE_START_X").map_or(0.0, |g| g.0);
        // Records: ceil(nv / per_line) lines each.
        let per_line = 80 / width;
        let lines_per = nv.div_ceil(per_line);
        let mut z = Vec::new();
        let mut rec: Vec<f64> = Vec::with_capacity(nv);
        let mut in_rec = 0;
        for (no, raw) in lines {
            let l = raw.trim_end_matches('\r');
            if l.trim().is_empty() {
                continue;
            }
            let want = (nv - rec.len()).min(per_line);
            for k in 0..want {
                let cell = l
                    .get(k * width..((k + 1) * width).min(l.len()))
                    .unwrap_or("")
                    .trim();
                if cell.eq_ignore_ascii_case("*missing*") {
                    return Err((no, "missing values (*missing*) are not supported".into()));
                }
                let v: f64 = cell.parse().map_err(|_| {
                    (
                        no,
                        format!("value {} of the line: not a number: {cell:?}", k + 1),
                    )
                })?;
                rec.push(v);
            }
            in_rec += 1;
            if in_rec == lines_per {
                z.append(&mut rec);
                in_rec = 0;
            }
        }
        if in_rec != 0 || z.len() < 2 * nv {
            return Err((
                text.lines().count(),
                "the data end inside a record, or hold fewer than two cross-sections".into(),
            ));
        }
        let nu = z.len() / nv;
        if let Some((ue, no)) = get("REFERENCE_LINE_END_U") {
            let want = get("REFERENCE_LINE_START_U").map_or(0.0, |g| g.0) + (nu - 1) as f64 * du;
            if (ue - want).abs() > 1e-6 * du.max(1.0) {
                return Err((no, format!("REFERENCE_LINE_END_U = {ue} but the data give {want} ({nu} cross-sections)")));
            }
        }
        Ok(CrgGrid {
            u0,
            du,
            v0,
            dv,
            nu,
            nv,
            z,
        })
    }

    /// Reads a CRG file; errors name the file and line.
    pub fn read(path: &Path) -> Result<CrgGrid, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        CrgGrid::parse(&text).map_err(|(line, m)| format!("{}:{line}: {m}", path.display()))
    }

    /// Cell and fractions of (x, y), clamped to the grid.
    fn locate(&self, x: f64, y: f64) -> (usize, usize, f64, f64) {
        let fu = ((x - self.u0) / self.du).clamp(0.0, (self.nu - 1) as f64);
        let fv = ((y - self.v0) / self.dv).clamp(0.0, (self.nv - 1) as f64);
        let i = (fu.floor() as usize).min(self.nu - 2);
        let j = (fv.floor() as usize).min(self.nv - 2);
        (i, j, fu - i as f64, fv - j as f64)
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.z[i * self.nv + j]
    }

    /// Height [m], bilinear in the cell.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let (i, j, a, b) = self.locate(x, y);
        let (z00, z10, z01, z11) = (
            self.at(i, j),
            self.at(i + 1, j),
            self.at(i, j + 1),
            self.at(i + 1, j + 1),
        );
        (1.0 - a) * ((1.0 - b) * z00 + b * z01) + a * ((1.0 - b) * z10 + b * z11)
    }

    /// Gradient (dz/dx, dz/dy); zero across a clamped direction outside the grid.
    pub fn slope(&self, x: f64, y: f64) -> (f64, f64) {
        let (i, j, a, b) = self.locate(x, y);
        let (z00, z10, z01, z11) = (
            self.at(i, j),
            self.at(i + 1, j),
            self.at(i, j + 1),
            self.at(i + 1, j + 1),
        );
        let inside_u = x >= self.u0 && x <= self.u0 + (self.nu - 1) as f64 * self.du;
        let inside_v = y >= self.v0 && y <= self.v0 + (self.nv - 1) as f64 * self.dv;
        let gx = ((1.0 - b) * (z10 - z00) + b * (z11 - z01)) / self.du;
        let gy = ((1.0 - a) * (z01 - z00) + a * (z11 - z10)) / self.dv;
        (
            if inside_u { gx } else { 0.0 },
            if inside_v { gy } else { 0.0 },
        )
    }

    /// Grid lines crossed by the line p + s d, s in [s0, s1] (bilinear cells: along x or
    /// y inside a cell the height is linear; along a skew line quadratic).
    pub fn kinks_along(&self, p: [f64; 2], d: [f64; 2], s0: f64, s1: f64, out: &mut Vec<f64>) {
        for i in 0..self.nu {
            push_x_crossing(p, d, self.u0 + i as f64 * self.du, s0, s1, out);
        }
        for j in 0..self.nv {
            push_y_crossing(p, d, self.v0 + j as f64 * self.dv, s0, s1, out);
        }
    }

    /// First and last x of the grid [m].
    pub fn x_range(&self) -> (f64, f64) {
        (self.u0, self.u0 + (self.nu - 1) as f64 * self.du)
    }

    /// Summary for logs.
    pub fn describe(&self) -> String {
        format!(
            "OpenCRG grid {} x {} (u {:.2}..{:.2} m every {} m, v {:.2}..{:.2} m every {} m)",
            self.nu,
            self.nv,
            self.x_range().0,
            self.x_range().1,
            self.du,
            self.v0,
            self.v0 + (self.nv - 1) as f64 * self.dv,
            self.dv
        )
    }
}
