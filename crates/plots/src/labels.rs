//! Where the point labels of a chart go: beside their markers, clear of each other.

/// An axis-aligned box (x0, y0, x1, y1) in px.
pub(crate) type Rect = (f64, f64, f64, f64);

pub(crate) fn overlap(a: Rect, b: Rect) -> f64 {
    let w = (a.2.min(b.2) - a.0.max(b.0)).max(0.0);
    let h = (a.3.min(b.3) - a.1.max(b.1)).max(0.0);
    w * h
}

/// Positions of the point labels: beside each marker, where the label covers no other label, no
/// marker and stays inside the plot (the least covered place when none is free).
/// `points`: (x, y, text width) per label; returns (x, y, text-anchor) per label.
pub(crate) fn place_labels(
    points: &[(f64, f64, f64)],
    plot: Rect,
) -> Vec<(f64, f64, &'static str)> {
    const H: f64 = 10.0;
    let markers: Vec<Rect> = points
        .iter()
        .map(|&(x, y, _)| (x - 4.0, y - 4.0, x + 4.0, y + 4.0))
        .collect();
    let mut placed: Vec<Rect> = Vec::new();
    let mut out = Vec::new();
    for &(x, y, w) in points {
        // (dx, dy of the baseline, anchor): right, left, above, below, the diagonals.
        let candidates = [
            (7.0, 4.0, "start"),
            (-7.0, 4.0, "end"),
            (0.0, -8.0, "middle"),
            (0.0, 16.0, "middle"),
            (6.0, -6.0, "start"),
            (6.0, 15.0, "start"),
            (-6.0, -6.0, "end"),
            (-6.0, 15.0, "end"),
        ];
        let rect = |(dx, dy, anchor): (f64, f64, &str)| {
            let x0 = match anchor {
                "start" => x + dx,
                "end" => x + dx - w,
                _ => x + dx - w / 2.0,
            };
            (x0, y + dy - H + 1.0, x0 + w, y + dy + 2.0)
        };
        let cost = |c: (f64, f64, &str)| {
            let r = rect(c);
            let outside = if r.0 < plot.0 || r.2 > plot.2 || r.1 < plot.1 || r.3 > plot.3 {
                1e6
            } else {
                0.0
            };
            let covered: f64 = placed.iter().chain(&markers).map(|p| overlap(r, *p)).sum();
            outside + covered
        };
        let best = candidates
            .iter()
            .copied()
            .min_by(|a, b| cost(*a).total_cmp(&cost(*b)))
            .unwrap();
        placed.push(rect(best));
        out.push((x + best.0, y + best.1, best.2));
    }
    out
}
