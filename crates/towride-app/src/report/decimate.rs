//! Dense traces reduced to what a pixel grid can show: per pixel column the first, the
//! smallest, the largest and the last value, in the order they occur. The path through
//! them is one continuous line that reaches every true extreme, with at most four points
//! per column whatever the number of samples.

/// Maps (x, y) data to pixel coordinates, drops non-finite points (a gap starts a new
/// piece) and keeps per pixel column the first, min, max and last point. Returns the
/// pieces as pixel-coordinate polylines.
pub fn pixel_path(
    pts: &[(f64, f64)],
    to_px: impl Fn(f64, f64) -> Option<(f64, f64)>,
) -> Vec<Vec<(f64, f64)>> {
    let mut pieces = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    // The column being gathered: its x and the first, min, max and last y (with the
    // order of min and max).
    struct Col {
        c: i64,
        x: f64,
        first: f64,
        lo: (usize, f64),
        hi: (usize, f64),
        last: f64,
        n: usize,
    }
    let flush = |col: &Col, out: &mut Vec<(f64, f64)>| {
        out.push((col.x, col.first));
        if col.n > 1 {
            let (a, b) = if col.lo.0 <= col.hi.0 {
                (col.lo.1, col.hi.1)
            } else {
                (col.hi.1, col.lo.1)
            };
            for y in [a, b, col.last] {
                if out.last() != Some(&(col.x, y)) {
                    out.push((col.x, y));
                }
            }
        }
    };
    let mut col: Option<Col> = None;
    for &(x, y) in pts {
        let Some((px, py)) = (x.is_finite() && y.is_finite())
            .then(|| to_px(x, y))
            .flatten()
            .filter(|(a, b)| a.is_finite() && b.is_finite())
        else {
            if let Some(c) = col.take() {
                flush(&c, &mut cur);
            }
            if !cur.is_empty() {
                pieces.push(std::mem::take(&mut cur));
            }
            continue;
        };
        let c = px.floor() as i64;
        match &mut col {
            Some(k) if k.c == c => {
                k.n += 1;
                if py < k.lo.1 {
                    k.lo = (k.n, py);
                }
                if py > k.hi.1 {
                    k.hi = (k.n, py);
                }
                k.last = py;
            }
            _ => {
                if let Some(k) = col.take() {
                    flush(&k, &mut cur);
                }
                col = Some(Col {
                    c,
                    x: px,
                    first: py,
                    lo: (0, py),
                    hi: (0, py),
                    last: py,
                    n: 1,
                });
            }
        }
    }
    if let Some(k) = col.take() {
        flush(&k, &mut cur);
    }
    if !cur.is_empty() {
        pieces.push(cur);
    }
    pieces
}
