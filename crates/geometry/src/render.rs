//! A small software rasteriser for the bearing surfaces: orthographic projection from a fixed
//! viewing direction, z-buffer, per-pixel Lambert shading of interpolated normals with two lights
//! (two-sided: the front and back faces get different colours, so folds read), the hodograph as a
//! polyline on top (depth-tested; its hidden parts drawn faint), a small axis triad, 2 × 2
//! supersampling, written as an 8-bit RGB PNG.

use crate::mesh::{bounds, norm, triangle_normal, unit};
use crate::GeometryError;

/// Options of [`render_png`].
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    /// Viewing direction: azimuth from the +x axis about z, and elevation above the xy-plane.
    pub azimuth_deg: f64,
    pub elevation_deg: f64,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            width: 480,
            height: 480,
            azimuth_deg: 35.0,
            elevation_deg: 25.0,
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
/// The same colour for both sides: where the torus covers a sheet twice with opposite
/// orientations (the P-surface of camera I folds the torus onto itself) a two-colour scheme
/// would show z-fighting patches instead of the shape.
const BACK: [f64; 3] = FRONT;
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
    h: usize,
}

fn dot(p: [f64; 3], q: [f64; 3]) -> f64 {
    p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
}

impl Camera {
    fn new(points: &[[f64; 3]], opts: &RenderOptions, w: usize, h: usize) -> Self {
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
        // Leave the bottom-left corner to the axis triad: the picture is centred a little above
        // the middle and fills at most 84 % of the height.
        let fit = |e: f64, side: f64| if e > 0.0 { side / e } else { 1.0 };
        let scale = fit(ext[0], 0.44 * w as f64).min(fit(ext[1], 0.41 * h as f64));
        Self {
            right,
            up,
            toward,
            center,
            scale,
            depth_lo: zlo * scale,
            depth_hi: zhi * scale,
            w,
            h,
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
            0.45 * self.h as f64 - self.scale * dot(d, self.up),
            dot(d, self.toward) * self.scale,
        ]
    }
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

    fn shade(n: [f64; 3], z: f64, cam: &Camera) -> [f64; 3] {
        let (n, base) = if dot(n, cam.toward) >= 0.0 {
            (n, FRONT)
        } else {
            (n.map(|x| -x), BACK)
        };
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
        let l = |v: [f64; 3]| dot(n, v.map(|x| x / norm(v))).max(0.0);
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
        let spec = 0.25 * dot(n, half).max(0.0).powi(24);
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

/// 3 × 5 bitmaps of the digits 1, 2, 3 (axis labels of the triad).
const DIGITS: [[u8; 5]; 3] = [
    [0b010, 0b110, 0b010, 0b010, 0b111],
    [0b111, 0b001, 0b111, 0b100, 0b111],
    [0b111, 0b001, 0b111, 0b001, 0b111],
];

fn digit(r: &mut Raster, d: usize, x: f64, y: f64, px: usize, color: [f64; 3]) {
    for (row, bits) in DIGITS[d].iter().enumerate() {
        for col in 0..3 {
            if bits & (0b100 >> col) == 0 {
                continue;
            }
            for yy in 0..px {
                for xx in 0..px {
                    let gx = x as i64 + (col * px + xx) as i64;
                    let gy = y as i64 + (row * px + yy) as i64;
                    if gx >= 0 && gy >= 0 && (gx as usize) < r.w && (gy as usize) < r.h {
                        r.color[gy as usize * r.w + gx as usize] = color;
                    }
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

/// Render a surface (vertices, triangles) with a polyline on it to PNG bytes.
pub fn render_png(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    curve: &[[f64; 3]],
    opts: &RenderOptions,
) -> Result<Vec<u8>, GeometryError> {
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
    let (w, h) = (opts.width as usize * SS, opts.height as usize * SS);
    let cam = Camera::new(vertices, opts, w, h);
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
    let bias = 0.01 * w as f64;
    let pc: Vec<[f64; 3]> = curve
        .iter()
        .filter(|p| p.iter().all(|x| x.is_finite()))
        .map(|p| cam.project(*p))
        .collect();
    for s in pc.windows(2) {
        r.line(s[0], s[1], 0.9 * SS as f64, CURVE, bias);
    }
    // Axis triad in the lower-left corner: e1 red, e2 green, e3 blue, labelled 1, 2, 3.
    let origin = [0.11 * w as f64, 0.955 * h as f64];
    let len = 0.055 * w.min(h) as f64;
    for (axis, color) in AXES.iter().enumerate() {
        let mut e = [0.0; 3];
        e[axis] = 1.0;
        let tip = [
            origin[0] + len * dot(e, cam.right),
            origin[1] - len * dot(e, cam.up),
        ];
        r.line(
            [origin[0], origin[1], f64::INFINITY],
            [tip[0], tip[1], f64::INFINITY],
            1.2 * SS as f64,
            *color,
            0.0,
        );
        let lx = origin[0] + 1.45 * len * dot(e, cam.right) - 3.0 * SS as f64;
        let ly = origin[1] - 1.45 * len * dot(e, cam.up) - 5.0 * SS as f64;
        digit(&mut r, axis, lx, ly, 2 * SS, *color);
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
    encode_png(&rgb, opts.width, opts.height)
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
