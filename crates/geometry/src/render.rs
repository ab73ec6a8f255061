//! A small software rasteriser for the bearing surfaces: orthographic projection from a fixed
//! viewing direction, z-buffer, per-pixel Lambert shading of interpolated normals with two lights
//! (two-sided), the hodograph as a polyline on top (depth-tested; its hidden parts drawn faint),
//! a title, an axis triad labelled 1, 2, 3 and a scale bar, 2 × 2 supersampling, written as an
//! 8-bit RGB PNG.

use crate::mesh::{bounds, norm, triangle_normal, unit};
use crate::text;
use crate::GeometryError;

/// Options of [`render_png`].
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    /// Viewing direction: azimuth from the +x axis about z, and elevation above the xy-plane.
    pub azimuth_deg: f64,
    pub elevation_deg: f64,
    /// Title lines at the top (the first larger), e.g. the surface and camera, then (a, b, m, h)
    /// and the torus; none: no title band.
    pub title: Vec<String>,
    /// A scale bar (a round length in the surface's units) at the bottom right; off when the
    /// axes are scaled differently (`--normalize-axes`).
    pub scale_bar: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            width: 480,
            height: 480,
            azimuth_deg: 35.0,
            elevation_deg: 25.0,
            title: Vec::new(),
            scale_bar: true,
        }
    }
}

/// Smallest and largest picture side in px (the 2 × 2 supersampled raster of the largest takes
/// about 180 MB).
pub const MIN_SIDE: u32 = 64;
pub const MAX_SIDE: u32 = 1200;

const SS: usize = 2;
const BACKGROUND: [f64; 3] = [1.0, 1.0, 1.0];
const FRONT: [f64; 3] = [0.95, 0.62, 0.32];
const CURVE: [f64; 3] = [0.55, 0.0, 0.1];
const AXES: [[f64; 3]; 3] = [[0.85, 0.1, 0.1], [0.1, 0.6, 0.1], [0.1, 0.2, 0.85]];

struct Camera {
    right: [f64; 3],
    up: [f64; 3],
    toward: [f64; 3],
    center: [f64; 3],
    scale: f64,
    /// Depth range of the scene (for depth cueing).
    depth_lo: f64,
    depth_hi: f64,
    w: usize,
    /// Vertical centre of the picture (px, down).
    middle: f64,
}

fn dot(p: [f64; 3], q: [f64; 3]) -> f64 {
    p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
}

impl Camera {
    /// A camera that fits `points` between the rows `top` and `bottom` (px).
    fn new(points: &[[f64; 3]], opts: &RenderOptions, w: usize, top: f64, bottom: f64) -> Self {
        let (az, el) = (
            opts.azimuth_deg.to_radians(),
            opts.elevation_deg.to_radians(),
        );
        // Unit vector from the scene toward the viewer.
        let toward = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
        let right = {
            let r = [-az.sin(), az.cos(), 0.0];
            let l = norm(r);
            r.map(|x| x / l)
        };
        let up = [
            toward[1] * right[2] - toward[2] * right[1],
            toward[2] * right[0] - toward[0] * right[2],
            toward[0] * right[1] - toward[1] * right[0],
        ];
        let (lo, hi) = bounds(points);
        let center: [f64; 3] = std::array::from_fn(|k| 0.5 * (lo[k] + hi[k]));
        let mut ext = [0.0f64; 2];
        let (mut zlo, mut zhi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in points {
            let d = [p[0] - center[0], p[1] - center[1], p[2] - center[2]];
            ext[0] = ext[0].max(dot(d, right).abs());
            ext[1] = ext[1].max(dot(d, up).abs());
            zlo = zlo.min(dot(d, toward));
            zhi = zhi.max(dot(d, toward));
        }
        let fit = |e: f64, side: f64| if e > 0.0 { side / e } else { 1.0 };
        let scale = fit(ext[0], 0.45 * w as f64).min(fit(ext[1], 0.47 * (bottom - top)));
        Self {
            right,
            up,
            toward,
            center,
            scale,
            depth_lo: zlo * scale,
            depth_hi: zhi * scale,
            w,
            middle: 0.5 * (top + bottom),
        }
    }

    /// Pixel x, pixel y (down), depth (larger: nearer the viewer).
    fn project(&self, p: [f64; 3]) -> [f64; 3] {
        let d = [
            p[0] - self.center[0],
            p[1] - self.center[1],
            p[2] - self.center[2],
        ];
        [
            0.5 * self.w as f64 + self.scale * dot(d, self.right),
            self.middle - self.scale * dot(d, self.up),
            dot(d, self.toward) * self.scale,
        ]
    }
}

#[derive(Clone, Copy)]
enum Anchor {
    Start,
    Middle,
}

struct Raster {
    w: usize,
    h: usize,
    color: Vec<[f64; 3]>,
    depth: Vec<f64>,
}

impl Raster {
    fn new(w: usize, h: usize) -> Self {
        Self {
            w,
            h,
            color: vec![BACKGROUND; w * h],
            depth: vec![f64::NEG_INFINITY; w * h],
        }
    }

    /// Two-sided lighting that does not depend on which side faces the viewer: each light counts
    /// with |n·l|. (Flipping the normal toward the viewer instead makes the brightness jump
    /// where an interpolated normal turns edge-on inside a visible sheet, as happens along the
    /// folds of these surfaces: the seams the pictures used to show.)
    fn shade(n: [f64; 3], z: f64, cam: &Camera) -> [f64; 3] {
        let base = FRONT;
        // Two lights in camera coordinates: key from upper left, fill from the right.
        let key = [
            0.5 * cam.toward[0] - 0.45 * cam.right[0] + 0.55 * cam.up[0],
            0.5 * cam.toward[1] - 0.45 * cam.right[1] + 0.55 * cam.up[1],
            0.5 * cam.toward[2] - 0.45 * cam.right[2] + 0.55 * cam.up[2],
        ];
        let fill = [
            0.6 * cam.toward[0] + 0.7 * cam.right[0] - 0.1 * cam.up[0],
            0.6 * cam.toward[1] + 0.7 * cam.right[1] - 0.1 * cam.up[1],
            0.6 * cam.toward[2] + 0.7 * cam.right[2] - 0.1 * cam.up[2],
        ];
        let n_len = norm(n);
        let n = if n_len > 0.0 {
            n.map(|x| x / n_len)
        } else {
            cam.toward
        };
        let l = |v: [f64; 3]| dot(n, v.map(|x| x / norm(v))).abs();
        // Blinn–Phong highlight of the key light, and depth cueing (farther: darker).
        let half = {
            let k = key.map(|x| x / norm(key));
            let hv = [
                k[0] + cam.toward[0],
                k[1] + cam.toward[1],
                k[2] + cam.toward[2],
            ];
            hv.map(|x| x / norm(hv))
        };
        let spec = 0.25 * dot(n, half).abs().powi(24);
        let range = cam.depth_hi - cam.depth_lo;
        let near = if range > 0.0 {
            ((z - cam.depth_lo) / range).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let cue = 0.6 + 0.4 * near;
        let i = (0.14 + 0.72 * l(key) + 0.25 * l(fill)) * cue;
        base.map(|c| (c * i + spec).min(1.0))
    }

    fn triangle(&mut self, p: [[f64; 3]; 3], n: [[f64; 3]; 3], cam: &Camera) {
        let x0 = p
            .iter()
            .map(|q| q[0])
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0) as usize;
        let x1 = p
            .iter()
            .map(|q| q[0])
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil();
        let y0 = p
            .iter()
            .map(|q| q[1])
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0) as usize;
        let y1 = p
            .iter()
            .map(|q| q[1])
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil();
        if !(x1.is_finite() && y1.is_finite()) {
            return;
        }
        let x1 = (x1 as usize).min(self.w - 1);
        let y1 = (y1 as usize).min(self.h - 1);
        let area =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        if area.abs() < 1e-12 {
            return;
        }
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let e = |a: [f64; 3], b: [f64; 3]| {
                    (b[0] - a[0]) * (py - a[1]) - (px - a[0]) * (b[1] - a[1])
                };
                let w0 = e(p[1], p[2]) / area;
                let w1 = e(p[2], p[0]) / area;
                let w2 = 1.0 - w0 - w1;
                if w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9 {
                    continue;
                }
                let z = w0 * p[0][2] + w1 * p[1][2] + w2 * p[2][2];
                let k = y * self.w + x;
                if z > self.depth[k] {
                    self.depth[k] = z;
                    let nn: [f64; 3] =
                        std::array::from_fn(|c| w0 * n[0][c] + w1 * n[1][c] + w2 * n[2][c]);
                    self.color[k] = Self::shade(nn, z, cam);
                }
            }
        }
    }

    fn blend(&mut self, x: i64, y: i64, color: [f64; 3], alpha: f64) {
        if x < 0 || y < 0 || x >= self.w as i64 || y >= self.h as i64 {
            return;
        }
        let k = y as usize * self.w + x as usize;
        let c = self.color[k];
        let a = alpha.clamp(0.0, 1.0);
        self.color[k] = std::array::from_fn(|i| c[i] * (1.0 - a) + color[i] * a);
    }

    /// Text of `size` px with its baseline at y; x is its left end, middle or right end.
    fn text(&mut self, s: &str, size: f64, x: f64, y: f64, color: [f64; 3], anchor: Anchor) {
        let width = text::width(s, size as f32) as f64;
        let x0 = match anchor {
            Anchor::Start => x,
            Anchor::Middle => x - width / 2.0,
        };
        let mut pixels = Vec::new();
        text::draw(s, size as f32, x0 as f32, y as f32, |px, py, cov| {
            pixels.push((px, py, cov as f64))
        });
        for (px, py, cov) in pixels {
            self.blend(px, py, color, cov);
        }
    }

    /// A circle of `radius` px drawn with a line of half-width `half`.
    fn ring(&mut self, c: [f64; 2], radius: f64, half: f64, color: [f64; 3]) {
        let n = (radius * 2.0).ceil().max(16.0) as usize;
        for k in 0..n {
            let (a, b) = (
                std::f64::consts::TAU * k as f64 / n as f64,
                std::f64::consts::TAU * (k + 1) as f64 / n as f64,
            );
            self.line(
                [
                    c[0] + radius * a.cos(),
                    c[1] + radius * a.sin(),
                    f64::INFINITY,
                ],
                [
                    c[0] + radius * b.cos(),
                    c[1] + radius * b.sin(),
                    f64::INFINITY,
                ],
                half,
                color,
                0.0,
            );
        }
    }

    fn disc(&mut self, c: [f64; 2], radius: f64, color: [f64; 3]) {
        let r = radius.ceil() as i64 + 1;
        for dy in -r..=r {
            for dx in -r..=r {
                let (x, y) = (c[0].floor() as i64 + dx, c[1].floor() as i64 + dy);
                let d2 = (x as f64 + 0.5 - c[0]).powi(2) + (y as f64 + 0.5 - c[1]).powi(2);
                if d2 <= radius * radius {
                    self.blend(x, y, color, 1.0);
                }
            }
        }
    }

    /// A line of `radius` px; where it is behind the surface (beyond `bias`) it is blended faintly.
    fn line(&mut self, a: [f64; 3], b: [f64; 3], radius: f64, color: [f64; 3], bias: f64) {
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let steps = (len / 0.5).ceil().max(1.0) as usize;
        let r = radius.ceil() as i64;
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let q: [f64; 3] = std::array::from_fn(|k| a[k] + t * (b[k] - a[k]));
            let (cx, cy) = (q[0].floor() as i64, q[1].floor() as i64);
            for dy in -r..=r {
                for dx in -r..=r {
                    let (x, y) = (cx + dx, cy + dy);
                    if x < 0 || y < 0 || x >= self.w as i64 || y >= self.h as i64 {
                        continue;
                    }
                    let d2 = (x as f64 + 0.5 - q[0]).powi(2) + (y as f64 + 0.5 - q[1]).powi(2);
                    if d2 > radius * radius {
                        continue;
                    }
                    let k = y as usize * self.w + x as usize;
                    let visible = q[2] + bias >= self.depth[k];
                    let alpha = if visible { 1.0 } else { 0.28 };
                    let c = self.color[k];
                    self.color[k] =
                        std::array::from_fn(|i| c[i] * (1.0 - alpha) + color[i] * alpha);
                }
            }
        }
    }
}

/// Vertex normals that ignore the orientation of the triangles: the image of a torus folds, and
/// across a fold the parametrisation reverses orientation, so oriented normals would cancel
/// there. Each incident face normal is added with the sign that agrees with the first one.
pub fn unoriented_normals(v: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<[f64; 3]> {
    let mut acc = vec![[0.0f64; 3]; v.len()];
    let mut reference: Vec<Option<[f64; 3]>> = vec![None; v.len()];
    for t in triangles {
        let n = triangle_normal(v, *t);
        if n == [0.0; 3] {
            continue;
        }
        for &i in t {
            let r = *reference[i as usize].get_or_insert(n);
            let sign = if dot(n, r) < 0.0 { -1.0 } else { 1.0 };
            for k in 0..3 {
                acc[i as usize][k] += sign * n[k];
            }
        }
    }
    acc.into_iter().map(unit).collect()
}

/// A viewing direction (azimuth, elevation in degrees) that shows a surface broadside: along its
/// axis of least spread (principal axes of the vertex cloud), tilted 35° toward the middle axis
/// so the depth still shows, and always from the side of positive components (a stable choice).
pub fn auto_view(vertices: &[[f64; 3]]) -> (f64, f64) {
    let n = vertices.len().max(1) as f64;
    let mean: [f64; 3] = std::array::from_fn(|k| vertices.iter().map(|p| p[k]).sum::<f64>() / n);
    let mut c = [[0.0f64; 3]; 3];
    for p in vertices {
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] += (p[i] - mean[i]) * (p[j] - mean[j]) / n;
            }
        }
    }
    let (values, vectors) = jacobi_eigen(c);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&p, &q| values[p].total_cmp(&values[q]));
    let col = |k: usize| [vectors[0][k], vectors[1][k], vectors[2][k]];
    let (least, middle) = (col(order[0]), col(order[1]));
    let (s_tilt, c_tilt) = (35f64.to_radians().sin(), 35f64.to_radians().cos());
    let mut d: [f64; 3] = std::array::from_fn(|k| c_tilt * least[k] + s_tilt * middle[k]);
    let l = norm(d);
    if !(l > 0.0 && l.is_finite()) {
        return (35.0, 25.0);
    }
    d = d.map(|x| x / l);
    if d[0] + d[1] + d[2] < 0.0 {
        d = d.map(|x| -x);
    }
    // Keep the picture's up close to +z: limit the elevation.
    // Between 20° and 70° of elevation (either sign): never edge-on to the horizontal plane, and
    // the picture's up stays close to the third axis.
    let el = d[2].clamp(-1.0, 1.0).asin().to_degrees();
    let el = el.signum() * el.abs().clamp(20.0, 70.0);
    let az = d[1].atan2(d[0]).to_degrees();
    (az, el)
}

/// Eigenvalues and eigenvectors (columns) of a symmetric 3 × 3 matrix by cyclic Jacobi rotations.
fn jacobi_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off < 1e-15 * (a[0][0].abs() + a[1][1].abs() + a[2][2].abs()) || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

fn validate(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    opts: &RenderOptions,
) -> Result<(), GeometryError> {
    for side in [opts.width, opts.height] {
        if !(MIN_SIDE..=MAX_SIDE).contains(&side) {
            return Err(GeometryError::Input(format!(
                "picture side {side} outside {MIN_SIDE}..={MAX_SIDE}"
            )));
        }
    }
    if !(opts.azimuth_deg.is_finite() && opts.elevation_deg.is_finite()) {
        return Err(GeometryError::Input("viewing angles must be finite".into()));
    }
    if vertices.is_empty() || vertices.iter().flatten().any(|x| !x.is_finite()) {
        return Err(GeometryError::Input("empty or non-finite mesh".into()));
    }
    if triangles
        .iter()
        .flatten()
        .any(|&i| i as usize >= vertices.len())
    {
        return Err(GeometryError::Input("triangle index out of range".into()));
    }
    Ok(())
}

/// Title sizes (output px) of the first and the other lines.
const TITLE_SIZE: [f64; 2] = [15.0, 12.5];

/// The shaded surface alone on a supersampled raster, with its camera (the rows above `top`
/// and below `bottom` are left to the title and to the triad and scale bar).
fn surface_raster(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    opts: &RenderOptions,
) -> (Raster, Camera) {
    let (w, h) = (opts.width as usize * SS, opts.height as usize * SS);
    let unit_px = SS as f64 * opts.width.min(opts.height) as f64 / 480.0;
    let top = if opts.title.is_empty() {
        12.0 * unit_px
    } else {
        (14.0 + TITLE_SIZE[0] + 5.0 + (TITLE_SIZE[1] + 5.0) * (opts.title.len() - 1) as f64)
            * unit_px
    };
    let bottom = h as f64 - 0.15 * h as f64;
    let cam = Camera::new(vertices, opts, w, top, bottom);
    let mut r = Raster::new(w, h);
    let normals = unoriented_normals(vertices, triangles);
    let proj: Vec<[f64; 3]> = vertices.iter().map(|p| cam.project(*p)).collect();
    for t in triangles {
        let [i, j, k] = t.map(|x| x as usize);
        // Align the vertex normals with the face before interpolating, so a normal never
        // passes through zero inside a triangle.
        let face = triangle_normal(vertices, *t);
        let align = |n: [f64; 3]| if dot(n, face) < 0.0 { n.map(|x| -x) } else { n };
        r.triangle(
            [proj[i], proj[j], proj[k]],
            [align(normals[i]), align(normals[j]), align(normals[k])],
            &cam,
        );
    }
    (r, cam)
}

/// How much the shading of a surface jumps: the fraction of neighbouring pixels on the same
/// sheet (depths within a pixel) whose brightness differs by more than 0.15 (of 1). A smooth
/// shading has none but where the surface is seen edge-on; a seam (normals that flip along a
/// line) shows as a line of such pairs.
pub fn shading_jumps(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    opts: &RenderOptions,
) -> Result<f64, GeometryError> {
    validate(vertices, triangles, opts)?;
    let (r, _) = surface_raster(vertices, triangles, opts);
    let luma = |c: [f64; 3]| 0.3 * c[0] + 0.59 * c[1] + 0.11 * c[2];
    let (mut pairs, mut jumps) = (0usize, 0usize);
    for y in 0..r.h - 1 {
        for x in 0..r.w - 1 {
            let k = y * r.w + x;
            for n in [k + 1, k + r.w] {
                let (d0, d1) = (r.depth[k], r.depth[n]);
                if !(d0.is_finite() && d1.is_finite()) || (d0 - d1).abs() > 1.0 {
                    continue;
                }
                pairs += 1;
                if (luma(r.color[k]) - luma(r.color[n])).abs() > 0.15 {
                    jumps += 1;
                }
            }
        }
    }
    Ok(jumps as f64 / pairs.max(1) as f64)
}

/// Render a surface (vertices, triangles) with a polyline on it to PNG bytes: the title lines of
/// `opts` at the top, the axis triad (1, 2, 3) at the bottom left, a scale bar at the bottom
/// right.
pub fn render_png(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    curve: &[[f64; 3]],
    opts: &RenderOptions,
) -> Result<Vec<u8>, GeometryError> {
    validate(vertices, triangles, opts)?;
    let (mut r, cam) = surface_raster(vertices, triangles, opts);
    let (w, h) = (r.w, r.h);
    let unit_px = SS as f64 * opts.width.min(opts.height) as f64 / 480.0;
    let bias = 0.01 * w as f64;
    let pc: Vec<[f64; 3]> = curve
        .iter()
        .filter(|p| p.iter().all(|x| x.is_finite()))
        .map(|p| cam.project(*p))
        .collect();
    for s in pc.windows(2) {
        r.line(s[0], s[1], 0.9 * SS as f64, CURVE, bias);
    }
    // Title.
    let mut y = 8.0 * unit_px;
    for (k, line) in opts.title.iter().enumerate() {
        let size = TITLE_SIZE[k.min(1)] * unit_px;
        y += size + if k == 0 { 0.0 } else { 5.0 * unit_px };
        let color = if k == 0 { [0.1; 3] } else { [0.3; 3] };
        r.text(line, size, w as f64 / 2.0, y, color, Anchor::Middle);
    }
    triad(&mut r, &cam, unit_px);
    if opts.scale_bar {
        scale_bar(&mut r, &cam, unit_px);
    }
    // 2 × 2 box filter.
    let (ow, oh) = (opts.width as usize, opts.height as usize);
    let mut rgb = Vec::with_capacity(ow * oh * 3);
    for y in 0..oh {
        for x in 0..ow {
            let mut acc = [0.0; 3];
            for dy in 0..SS {
                for dx in 0..SS {
                    let c = r.color[(y * SS + dy) * w + x * SS + dx];
                    for k in 0..3 {
                        acc[k] += c[k];
                    }
                }
            }
            for v in acc {
                rgb.push((v / (SS * SS) as f64 * 255.0).round().clamp(0.0, 255.0) as u8);
            }
        }
    }
    let _ = h;
    encode_png(&rgb, opts.width, opts.height)
}

/// The axis triad in the lower-left corner: e1 red, e2 green, e3 blue, each labelled with its
/// number beyond its tip; an axis seen end-on is a circle with a dot (toward the viewer) or a
/// cross (away). Labels are placed where they overlap no other label and stay in the picture.
fn triad(r: &mut Raster, cam: &Camera, unit_px: f64) {
    let len = 26.0 * unit_px;
    let size = 14.0 * unit_px;
    let origin = [len + 22.0 * unit_px, r.h as f64 - len - 20.0 * unit_px];
    let mut boxes: Vec<[f64; 4]> = Vec::new();
    for (axis, color) in AXES.iter().enumerate() {
        let mut e = [0.0; 3];
        e[axis] = 1.0;
        let d = [dot(e, cam.right), -dot(e, cam.up)];
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if l > 0.25 {
            let tip = [origin[0] + len * d[0], origin[1] + len * d[1]];
            r.line(
                [origin[0], origin[1], f64::INFINITY],
                [tip[0], tip[1], f64::INFINITY],
                1.2 * SS as f64,
                *color,
                0.0,
            );
        } else {
            let toward = dot(e, cam.toward) > 0.0;
            r.ring(origin, 5.0 * unit_px, 1.1 * SS as f64, *color);
            if toward {
                r.disc(origin, 1.8 * unit_px, *color);
            } else {
                let c = 3.2 * unit_px;
                for s in [-1.0, 1.0] {
                    r.line(
                        [origin[0] - c, origin[1] - s * c, f64::INFINITY],
                        [origin[0] + c, origin[1] + s * c, f64::INFINITY],
                        0.9 * SS as f64,
                        *color,
                        0.0,
                    );
                }
            }
        }
        // The label: beyond the tip along the axis, else the nearest free place around it.
        let label = ["1", "2", "3"][axis];
        let (tw, th) = (text::width(label, size as f32) as f64, 0.72 * size);
        let base_angle = if l > 0.25 { d[1].atan2(d[0]) } else { -0.75 };
        let reach = if l > 0.25 {
            len * l + 11.0 * unit_px
        } else {
            13.0 * unit_px
        };
        let mut chosen = None;
        'search: for step in 0..12 {
            for sign in [1.0, -1.0] {
                let a = base_angle + sign * step as f64 * 0.35;
                let c = [origin[0] + reach * a.cos(), origin[1] + reach * a.sin()];
                let b = [
                    c[0] - tw / 2.0,
                    c[1] - th / 2.0,
                    c[0] + tw / 2.0,
                    c[1] + th / 2.0,
                ];
                let inside = b[0] >= 0.0 && b[1] >= 0.0 && b[2] <= r.w as f64 && b[3] <= r.h as f64;
                let free = boxes.iter().all(|o| {
                    b[2] + 2.0 < o[0] || o[2] + 2.0 < b[0] || b[3] + 2.0 < o[1] || o[3] + 2.0 < b[1]
                });
                if inside && free {
                    chosen = Some(b);
                    break 'search;
                }
                if step == 0 {
                    break;
                }
            }
        }
        let b = chosen.unwrap_or_else(|| {
            let c = [
                origin[0] + reach * base_angle.cos(),
                origin[1] + reach * base_angle.sin(),
            ];
            [
                c[0] - tw / 2.0,
                c[1] - th / 2.0,
                c[0] + tw / 2.0,
                c[1] + th / 2.0,
            ]
        });
        r.text(label, size, b[0], b[3], *color, Anchor::Start);
        boxes.push(b);
    }
}

/// A bar of a round length (1, 2 or 5 × 10ᵏ in the surface's units, about a fifth of the
/// width) at the bottom right, with its length written above it.
fn scale_bar(r: &mut Raster, cam: &Camera, unit_px: f64) {
    let target = 0.2 * r.w as f64 / cam.scale;
    if !(target.is_finite() && target > 0.0) {
        return;
    }
    let mag = 10f64.powf(target.log10().floor());
    let length = [5.0, 2.0, 1.0]
        .iter()
        .map(|m| m * mag)
        .find(|l| *l <= target)
        .unwrap_or(mag);
    let px = length * cam.scale;
    let x1 = r.w as f64 - 18.0 * unit_px;
    let (x0, y) = (x1 - px, r.h as f64 - 22.0 * unit_px);
    let ink = [0.2; 3];
    let inf = f64::INFINITY;
    r.line([x0, y, inf], [x1, y, inf], 1.0 * SS as f64, ink, 0.0);
    for x in [x0, x1] {
        r.line(
            [x, y - 5.0 * unit_px, inf],
            [x, y + 5.0 * unit_px, inf],
            0.8 * SS as f64,
            ink,
            0.0,
        );
    }
    let digits = (-length.log10().floor()).max(0.0) as usize;
    let label = format!("{length:.digits$}");
    r.text(
        &label,
        12.5 * unit_px,
        (x0 + x1) / 2.0,
        y - 8.0 * unit_px,
        ink,
        Anchor::Middle,
    );
}

fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, GeometryError> {
    let mut buf = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut buf, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::High);
        let png_err =
            |e: png::EncodingError| GeometryError::Numerical(format!("PNG encoding: {e}"));
        let mut writer = enc.write_header().map_err(png_err)?;
        writer.write_image_data(rgb).map_err(png_err)?;
    }
    Ok(buf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_view_looks_along_the_thin_axis() {
        // A flat cloud in the plane z = 2x: the least-spread axis is (−2, 0, 1)/√5.
        let pts: Vec<[f64; 3]> = (0..400)
            .map(|i| {
                let (u, w) = ((i % 20) as f64, (i / 20) as f64 * 0.5);
                [u, w, 2.0 * u + 0.001 * (i as f64).sin()]
            })
            .collect();
        let (az, el) = auto_view(&pts);
        let d = [
            el.to_radians().cos() * az.to_radians().cos(),
            el.to_radians().cos() * az.to_radians().sin(),
            el.to_radians().sin(),
        ];
        let normal = [-2.0 / 5f64.sqrt(), 0.0, 1.0 / 5f64.sqrt()];
        let cos = dot(d, normal).abs();
        assert!(
            (cos - 35f64.to_radians().cos()).abs() < 0.02,
            "{az} {el} {cos}"
        );
    }
}
