//! `rsts surfaces`: the bearing surfaces of one integral manifold (seed sec. 3, Table 2) — the
//! P-surface (ω, body frame) and Π-surface (Ω = Qω, fixed frame) of each torus as PLY meshes
//! from a grid in the angles (ψ₁, ψ₂), shaded PNG pictures with the hodograph drawn on them, and
//! an MCAP scene of Poinsot's picture (the P-surface rolling with the body while the fixed
//! hodograph traces the Π-surface).

use std::io::Write;
use std::path::PathBuf;

use anyhow::{bail, Context};
use clap::Args as ClapArgs;

use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_geometry::mesh::{hodograph, Surface, TorusMesh, MAX_GRID, MIN_GRID};
use rsts_geometry::ply::ply_text;
use rsts_geometry::render::{auto_view, render_png, RenderOptions, MAX_SIDE, MIN_SIDE};
use rsts_geometry::scene::write_scene;

use crate::args::{case_error, count, finite_f64, FieldArgs};

/// Shown at the end of `rsts surfaces --help`.
pub const EXAMPLES: &str = "\
Examples:
  # every torus of camera V (a = 1, b = 0.5): PLY, PNG and the MCAP scene in out/V
  rsts surfaces --m -0.7092 --h 1.5643 --out out/V

  # one torus, only the pictures (those of docs/geometry.md: scripts/make_pictures.sh)
  rsts surfaces --a 1 --b 0.5 --m 0.3 --h -0.375 --torus 0 --out out/I+ --no-mcap --no-ply

  # finer mesh, other view, longer hodograph
  rsts surfaces --m -2.9877 --h 3.2858 --grid 128 --azimuth 60 --elevation 15 --periods 10 --out out/VI

Open a scene torusK_scene.mcap in Foxglove or Lichtblick (Open local file) with the layout
docs/foxglove/surfaces.json (Layouts > Import layout); see docs/mcap.md.";

/// Largest `--grid` (PLY meshes and pictures) and `--scene-grid` (the MCAP scene, whose meshes
/// are JSON: about 1 kB of memory per vertex while it is written).
pub const MAX_MESH_GRID: usize = 512;
pub const MAX_SCENE_GRID: usize = 256;
/// Most bytes all files of one run may take (estimated before any work).
pub const MAX_TOTAL_BYTES: f64 = 512.0 * 1024.0 * 1024.0;

/// Estimated bytes of the files of one torus, measured (PLY 175 B per grid point, the scene
/// 46 B per scene-grid point and 170 B per hodograph sample, a PNG at most 4 B per pixel).
fn bytes_per_torus(args: &Args) -> f64 {
    let g = args.grid as f64;
    let sg = args.scene_grid as f64;
    let px = f64::from(args.size) * f64::from(args.size);
    let ply = if args.no_ply {
        0.0
    } else {
        2.0 * 175.0 * g * g
    };
    let scene = if args.no_mcap {
        0.0
    } else {
        46.0 * sg * sg + 170.0 * args.samples as f64
    };
    ply + scene + 2.0 * 4.0 * px
}

/// Options of `rsts surfaces`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    #[command(flatten)]
    pub fields: FieldArgs,
    /// Integral constant m
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_hyphen_values = true)]
    pub m: f64,
    /// Energy h
    #[arg(long, value_name = "H", value_parser = finite_f64, allow_hyphen_values = true)]
    pub h: f64,
    /// Only this torus (0..tori); default: every torus of the integral manifold
    #[arg(long, value_name = "K")]
    pub torus: Option<usize>,
    /// Output directory (created; each file in it is written whole or not at all)
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Grid size per angle of the PLY meshes and pictures (4 to 512)
    #[arg(long, value_name = "N", default_value = "96", value_parser = count)]
    pub grid: usize,
    /// Grid size per angle of the surfaces in the MCAP scene (4 to 256)
    #[arg(long, value_name = "N", default_value = "64", value_parser = count)]
    pub scene_grid: usize,
    /// Picture size in px (square)
    #[arg(long, value_name = "PX", default_value = "480")]
    pub size: u32,
    /// Viewing azimuth in degrees (about the third axis, from the first); default: each surface
    /// seen broadside (along its axis of least spread, tilted 35°)
    #[arg(long, value_parser = finite_f64, allow_hyphen_values = true)]
    pub azimuth: Option<f64>,
    /// Viewing elevation in degrees (default as for --azimuth; 25 if only --azimuth is given)
    #[arg(long, value_parser = finite_f64, allow_hyphen_values = true)]
    pub elevation: Option<f64>,
    /// Length of the hodograph, in units of the longer of the two angle periods
    #[arg(long, value_name = "P", default_value = "3", value_parser = finite_f64)]
    pub periods: f64,
    /// Samples of the hodograph
    #[arg(long, value_name = "N", default_value = "3000", value_parser = count)]
    pub samples: usize,
    /// Initial angles ψ1,ψ2 of the hodograph on the torus
    #[arg(long, value_name = "PSI1,PSI2", default_value = "0.3,1.1", value_parser = pair, allow_hyphen_values = true)]
    pub phases: (f64, f64),
    /// Pictures only: scale each coordinate to the same range before drawing (for needle-like
    /// surfaces, e.g. camera I-; the meshes and the scene keep the true coordinates)
    #[arg(long)]
    pub normalize_axes: bool,
    /// Do not write the PLY meshes
    #[arg(long)]
    pub no_ply: bool,
    /// Do not write the MCAP scene
    #[arg(long)]
    pub no_mcap: bool,
}

fn pair(s: &str) -> Result<(f64, f64), String> {
    let parts: Vec<&str> = s.split(',').collect();
    let [p, q] = parts[..] else {
        return Err(format!(
            "expected two numbers PSI1,PSI2, got '{}'",
            rsts_io::cut(s)
        ));
    };
    Ok((finite_f64(p)?, finite_f64(q)?))
}

/// The vertices and the curve with each coordinate divided by the surface's range in it.
fn normalize_axes(verts: &[[f64; 3]], curve: &[[f64; 3]]) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let (lo, hi) = rsts_geometry::mesh::bounds(verts);
    let range: [f64; 3] = std::array::from_fn(|k| {
        let r = hi[k] - lo[k];
        if r > 0.0 && r.is_finite() {
            r
        } else {
            1.0
        }
    });
    let scale = |p: &[f64; 3]| -> [f64; 3] { std::array::from_fn(|k| p[k] / range[k]) };
    (
        verts.iter().map(scale).collect(),
        curve.iter().map(scale).collect(),
    )
}

pub fn run(args: Args, _out: &mut dyn Write) -> anyhow::Result<()> {
    for (name, n, max) in [
        ("--grid", args.grid, MAX_MESH_GRID),
        ("--scene-grid", args.scene_grid, MAX_SCENE_GRID),
    ] {
        if !(MIN_GRID..=max.min(MAX_GRID)).contains(&n) {
            bail!("{name} must be in {MIN_GRID}..={max}, got {n}");
        }
    }
    if !(MIN_SIDE..=MAX_SIDE).contains(&args.size) {
        bail!(
            "--size must be in {MIN_SIDE}..={MAX_SIDE} px, got {}",
            args.size
        );
    }
    if !(args.periods > 0.0 && args.periods <= 1e4) {
        bail!("--periods must be in (0, 1e4], got {}", args.periods);
    }
    if !(2..=1_000_000).contains(&args.samples) {
        bail!("--samples must be in 2..=1000000, got {}", args.samples);
    }
    let choice = |torus| TorusChoice {
        torus,
        phase1: args.phases.0,
        phase2: args.phases.1,
    };
    let first = ExplicitMotion::<f64>::new(args.fields.a, args.fields.b, args.m, args.h, choice(0))
        .map_err(case_error)?;
    let tori: Vec<usize> = match args.torus {
        Some(k) if k >= first.tori => bail!(
            "--torus {k}: camera {} has {}",
            first.camera,
            rsts_closed_form::tori_phrase(first.tori)
        ),
        Some(k) => vec![k],
        None => (0..first.tori).collect(),
    };
    let total = bytes_per_torus(&args) * tori.len() as f64;
    if total > MAX_TOTAL_BYTES {
        bail!(
            "--grid/--scene-grid/--samples/--size: the files of {} torus/tori would take about {} bytes, more than the {} bytes (512 MiB) one run may write; use a smaller grid, fewer samples, --torus K, --no-ply or --no-mcap",
            tori.len(),
            rsts_dynamics::short(total),
            rsts_dynamics::short(MAX_TOTAL_BYTES)
        );
    }
    rsts_io::check_writable_dir(&args.out)
        .with_context(|| format!("--out {}", args.out.display()))?;
    let view = |verts: &[[f64; 3]], title: Vec<String>| -> RenderOptions {
        let (az, el) = match (args.azimuth, args.elevation) {
            (None, None) => auto_view(verts),
            (az, el) => (az.unwrap_or(35.0), el.unwrap_or(25.0)),
        };
        RenderOptions {
            width: args.size,
            height: args.size,
            azimuth_deg: az,
            elevation_deg: el,
            title,
            scale_bar: !args.normalize_axes,
        }
    };
    // Numbers as in the paper: a true minus sign.
    let num = |x: f64| format!("{x}").replace('-', "−");
    eprintln!(
        "camera {} (a = {}, b = {}, m = {}, h = {}), {} torus/tori",
        first.camera, args.fields.a, args.fields.b, args.m, args.h, first.tori
    );
    for k in tori {
        let motion =
            ExplicitMotion::<f64>::new(args.fields.a, args.fields.b, args.m, args.h, choice(k))?;
        let mesh = TorusMesh::new(&motion, args.grid, args.grid)?;
        let [p1, p2] = motion.periods();
        let t_end = args.periods * p1.max(p2);
        let hod = hodograph(&motion, t_end, args.samples)?;
        let write = |name: String, bytes: &[u8]| -> anyhow::Result<PathBuf> {
            let path = args.out.join(name);
            rsts_io::write_atomic(&path, bytes)
                .with_context(|| format!("--out: writing {}", path.display()))?;
            Ok(path)
        };
        let mut written = Vec::new();
        for surface in Surface::BOTH {
            let (verts, curve) = match surface {
                Surface::P => (&mesh.omega, &hod.omega),
                Surface::Pi => (&mesh.omega_fixed, &hod.omega_fixed),
            };
            let stem = format!("torus{k}_{}", surface.file_stem());
            if !args.no_ply {
                let comment = format!(
                    "rsts {}: camera {}, a = {}, b = {}, m = {}, h = {}, torus {k}, grid {n}x{n} in (psi1, psi2)",
                    surface.title(),
                    motion.camera,
                    args.fields.a,
                    args.fields.b,
                    args.m,
                    args.h,
                    n = args.grid
                );
                let text = ply_text(verts, &mesh.triangles, Some(&mesh.angles), &comment);
                written.push(write(format!("{stem}.ply"), text.as_bytes())?);
            }
            let tori = match motion.tori {
                1 => "1 torus".to_string(),
                n => format!("{n} tori"),
            };
            let mut title = vec![
                format!(
                    "{}, camera {}",
                    surface.title(),
                    motion.camera.to_string().replace('-', "−")
                ),
                format!(
                    "a = {}, b = {}, m = {}, h = {}, torus {k} ({tori})",
                    num(args.fields.a),
                    num(args.fields.b),
                    num(args.m),
                    num(args.h),
                ),
            ];
            if args.normalize_axes {
                title.push("each axis scaled to the same extent".into());
            }
            let png = if args.normalize_axes {
                let (v, c) = normalize_axes(verts, curve);
                render_png(&v, &mesh.triangles, &c, &view(&v, title))?
            } else {
                render_png(verts, &mesh.triangles, curve, &view(verts, title))?
            };
            written.push(write(format!("{stem}.png"), &png)?);
        }
        if !args.no_mcap {
            let scene_mesh = if args.scene_grid == args.grid {
                mesh.clone()
            } else {
                TorusMesh::new(&motion, args.scene_grid, args.scene_grid)?
            };
            let path = args.out.join(format!("torus{k}_scene.mcap"));
            write_scene(&path, &scene_mesh, &hod)
                .map_err(|e| anyhow::anyhow!("--out: {}", rsts_io::error_text(&e)))?;
            written.push(path);
        }
        for p in written {
            eprintln!("wrote {}", p.display());
        }
    }
    Ok(())
}
