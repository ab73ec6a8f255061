//! Placement of the camera labels: a chamfer distance transform on a pixel raster of each
//! camera, the ink boxes of a label, and anchors for cameras thinner than the raster.

use crate::camera::Camera;

use super::regions::{camera_at, classify, Chain, Frame, Geometry};

/// Where a camera's label goes.
#[derive(Clone, Copy, Debug)]
pub(super) struct LabelPlacement {
    pub(super) camera: Camera,
    pub(super) tori: usize,
    /// A point well inside the camera (px).
    pub(super) anchor: (f64, f64),
    /// Centre of the label text (px); differs from `anchor` when the label does not fit in the
    /// camera and is set outside with a leader line.
    pub(super) text: (f64, f64),
    /// Distance (px, about) from the anchor to the camera's boundary; 0 for a camera too thin for
    /// the raster.
    pub(super) room: f64,
}

/// Chamfer 3-4 distance of each cell of the mask to the nearest cell outside it (cells beyond
/// the raster count as outside).
fn distance_transform(inside: &[bool], nx: usize, ny: usize) -> Vec<u32> {
    let big = u32::MAX / 4;
    let mut d: Vec<u32> = inside.iter().map(|&x| if x { big } else { 0 }).collect();
    let at = |i: usize, j: usize| j * nx + i;
    for j in 0..ny {
        for i in 0..nx {
            let k = at(i, j);
            if d[k] == 0 {
                continue;
            }
            let mut v = d[k];
            if i == 0 || j == 0 || i + 1 == nx || j + 1 == ny {
                v = v.min(3);
            }
            if i > 0 {
                v = v.min(d[at(i - 1, j)] + 3);
            }
            if j > 0 {
                v = v.min(d[at(i, j - 1)] + 3);
                if i > 0 {
                    v = v.min(d[at(i - 1, j - 1)] + 4);
                }
                if i + 1 < nx {
                    v = v.min(d[at(i + 1, j - 1)] + 4);
                }
            }
            d[k] = v;
        }
    }
    for j in (0..ny).rev() {
        for i in (0..nx).rev() {
            let k = at(i, j);
            if d[k] == 0 {
                continue;
            }
            let mut v = d[k];
            if i + 1 < nx {
                v = v.min(d[at(i + 1, j)] + 3);
            }
            if j + 1 < ny {
                v = v.min(d[at(i, j + 1)] + 3);
                if i + 1 < nx {
                    v = v.min(d[at(i + 1, j + 1)] + 4);
                }
                if i > 0 {
                    v = v.min(d[at(i - 1, j + 1)] + 4);
                }
            }
            d[k] = v;
        }
    }
    d
}

/// The ink of a label centred at (x, y): the name (bold 17 px, baseline y − 1) and the number of
/// tori (11 px, baseline y + 12), as rectangles (x, y, w, h) grown by `pad` px.
fn label_boxes(camera: Camera, x: f64, y: f64, pad: f64) -> [(f64, f64, f64, f64); 2] {
    let name_w = 11.0 * camera.label().len() as f64 + 2.0;
    let tori_w = 31.0;
    [
        (
            x - 0.5 * name_w - pad,
            y - 13.0 - pad,
            name_w + 2.0 * pad,
            13.0 + 2.0 * pad,
        ),
        (
            x - 0.5 * tori_w - pad,
            y + 3.0 - pad,
            tori_w + 2.0 * pad,
            10.0 + 2.0 * pad,
        ),
    ]
}

/// Where to put each camera's label: the point of a pixel raster of the camera farthest from
/// its boundary (the pole of inaccessibility, by a chamfer distance transform), preferring a
/// point where the label's ink fits in the camera. When it fits nowhere, the text goes to the
/// nearest empty (inadmissible) place where it fits, with a leader line to the anchor.
///
/// Only the `cameras` listed get a label; `thin` gives an anchor (px) and the number of tori for
/// cameras the raster misses (thinner than its step).
pub(super) fn label_positions(
    g: &Geometry,
    f: &Frame,
    cameras: &[Camera],
    thin: &[(Camera, (f64, f64), usize)],
) -> Vec<LabelPlacement> {
    // About 3 px cells, at most ~60 000 of them.
    let step = (f.w * f.h / 60_000.0).sqrt().max(3.0);
    let nx = (f.w / step).floor() as usize;
    let ny = (f.h / step).floor() as usize;
    let mut cells: Vec<Option<Camera>> = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let x = f.x0 + (i as f64 + 0.5) * step;
            let y = f.y0 + (j as f64 + 0.5) * step;
            cells.push(camera_at(g.a, g.b, f.m_of(x), f.h_of(y)));
        }
    }
    let at = |i: usize, j: usize| j * nx + i;
    let centre = |k: usize| {
        (
            f.x0 + ((k % nx) as f64 + 0.5) * step,
            f.y0 + ((k / nx) as f64 + 0.5) * step,
        )
    };
    // Do all cells that meet the rectangles lie in the mask?
    let in_mask = |mask: &[bool], boxes: &[(f64, f64, f64, f64)]| {
        boxes.iter().all(|&(x, y, w, h)| {
            let i0 = ((x - f.x0) / step).floor();
            let i1 = ((x + w - f.x0) / step).floor();
            let j0 = ((y - f.y0) / step).floor();
            let j1 = ((y + h - f.y0) / step).floor();
            if i0 < 0.0 || j0 < 0.0 || i1 >= nx as f64 || j1 >= ny as f64 {
                return false;
            }
            let (i0, i1, j0, j1) = (i0 as usize, i1 as usize, j0 as usize, j1 as usize);
            (j0..=j1).all(|j| (i0..=i1).all(|i| mask[at(i, j)]))
        })
    };
    let mark = |mask: &mut [bool], boxes: &[(f64, f64, f64, f64)]| {
        for &(x, y, w, h) in boxes {
            let i0 = ((x - f.x0) / step).floor().max(0.0) as usize;
            let j0 = ((y - f.y0) / step).floor().max(0.0) as usize;
            let i1 = (((x + w - f.x0) / step).floor().max(0.0) as usize).min(nx - 1);
            let j1 = (((y + h - f.y0) / step).floor().max(0.0) as usize).min(ny - 1);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    mask[at(i, j)] = false;
                }
            }
        }
    };
    // Empty (inadmissible) cells not yet taken by a label set outside its camera.
    let mut empty: Vec<bool> = cells.iter().map(|c| c.is_none()).collect();
    let mut out = Vec::new();
    for &camera in cameras {
        let inside: Vec<bool> = cells.iter().map(|c| *c == Some(camera)).collect();
        let (anchor, tori, fits, room) = if inside.iter().any(|&x| x) {
            let d = distance_transform(&inside, nx, ny);
            let mut order: Vec<usize> = (0..d.len()).filter(|&k| d[k] > 0).collect();
            order.sort_by(|&p, &q| d[q].cmp(&d[p]).then(p.cmp(&q)));
            let fitting = order.iter().copied().find(|&k| {
                let (x, y) = centre(k);
                in_mask(&inside, &label_boxes(camera, x, y, 2.0))
            });
            let best = fitting.unwrap_or(order[0]);
            let (x, y) = centre(best);
            let tori = classify(g.a, g.b, f.m_of(x), f.h_of(y)).map_or(0, |(_, t)| t);
            let room = d[order[0]] as f64 / 3.0 * step;
            (centre(best), tori, fitting.is_some(), room)
        } else if let Some(&(_, anchor, tori)) = thin.iter().find(|t| t.0 == camera) {
            (anchor, tori, false, 0.0)
        } else {
            continue;
        };
        let text = if fits {
            anchor
        } else {
            // Nearest empty place at least 36 px away; it is then taken.
            let spot = (0..cells.len())
                .filter(|&k| empty[k])
                .map(|k| {
                    let c = centre(k);
                    (c, (c.0 - anchor.0).hypot(c.1 - anchor.1))
                })
                .filter(|&(_, dist)| dist >= 36.0)
                .filter(|&(c, _)| in_mask(&empty, &label_boxes(camera, c.0, c.1, 6.0)))
                .min_by(|p, q| p.1.total_cmp(&q.1))
                .map(|(c, _)| c);
            match spot {
                Some(c) => {
                    mark(&mut empty, &label_boxes(camera, c.0, c.1, 10.0));
                    c
                }
                None => anchor,
            }
        };
        out.push(LabelPlacement {
            camera,
            tori,
            anchor,
            text,
            room,
        });
    }
    out
}

/// Anchors (px) for cameras that the label raster misses but the strip sweep found.
pub(super) fn thin_anchors(
    g: &Geometry,
    f: &Frame,
    chains: &[Chain],
) -> Vec<(Camera, (f64, f64), usize)> {
    let mut out: Vec<(Camera, (f64, f64), usize)> = Vec::new();
    for camera in Camera::ALL {
        let best = chains
            .iter()
            .filter(|c| c.camera == camera)
            .max_by(|p, q| p.widest.2.total_cmp(&q.widest.2));
        if let Some(ch) = best {
            let (m, h, _) = ch.widest;
            let tori = classify(g.a, g.b, m, h).map_or(0, |(_, t)| t);
            out.push((camera, (f.px(m), f.py(h)), tori));
        }
    }
    out
}
