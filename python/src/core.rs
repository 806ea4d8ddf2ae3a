//! The one bridge between the Python module and the ophis library: every `ophis::` path the
//! bindings use is in this file, so that when the library moves things the fix is here.
//!
//! Nothing here knows Python. It speaks plain Rust — paths, strings, flat `f32` buffers,
//! [`Error`] — and `lib.rs` turns that into Python objects and exceptions.

use ophis::film::Film;
use ophis::image_io::{
    read_exr_metadata, read_image, write_exr, write_exr_channels, write_png, ImageError, RgbImage,
};
use ophis::integrator::PathStrategy;
use ophis::merge::{decode_tile_spp, render_metadata, SceneIdentity, KEY_AOVS, KEY_TILE_SPP};
use ophis::optics::filmstack::FilmStack;
use ophis::optics::filmtool::{parse_index, rt_deg, stack_rgb};
use ophis::optics::ior::Ior;
use ophis::optics::stackspec::parse_items;
use ophis::render::{render_with, Progress, RenderControl, RenderOptions, TileOrder};
use ophis::scene::build::{build_material, load_scene, load_scene_str, LoadOptions};
use ophis::scene::builtin::XENOPELTIS_XML;
use ophis::scene::mitsuba::{self, Node, SceneError};
use ophis::scene::Scene;
use ophis::tools::inspect::{at_wavelength, bsdf_ids, find_bsdf, linear_srgb, Quantity};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// A failure, sorted by the Python exception it becomes.
#[derive(Debug)]
pub enum Error {
    /// A scene problem at a known place: `ophis.SceneError`.
    Scene(Located),
    /// A file that could not be read or written: `OSError` (`FileNotFoundError` if `missing`).
    Io { message: String, missing: bool },
    /// A bad argument or malformed input without a location: `ValueError`.
    Value(String),
}

/// A message with its file, line and column (1-based).
#[derive(Debug, Clone)]
pub struct Located {
    pub file: String,
    pub line: u32,
    pub column: u32,
    /// The message without the location.
    pub message: String,
}

impl From<SceneError> for Error {
    fn from(e: SceneError) -> Error {
        match &e {
            SceneError::Io { source, .. } => Error::Io {
                missing: source.kind() == std::io::ErrorKind::NotFound,
                message: e.to_string(),
            },
            SceneError::Xml { loc, message } | SceneError::At { loc, message } => {
                let message = match e {
                    SceneError::Xml { .. } => format!("malformed XML: {message}"),
                    _ => message.clone(),
                };
                Error::Scene(Located {
                    file: loc.file.display().to_string(),
                    line: loc.line,
                    column: loc.col,
                    message,
                })
            }
        }
    }
}

impl From<ImageError> for Error {
    fn from(e: ImageError) -> Error {
        match e {
            ImageError::Missing { .. } => Error::Io {
                message: e.to_string(),
                missing: true,
            },
            ImageError::IsDirectory { .. } | ImageError::Io { .. } | ImageError::Write { .. } => {
                Error::Io {
                    message: e.to_string(),
                    missing: false,
                }
            }
            other => Error::Value(other.to_string()),
        }
    }
}

/// Where a scene's XML comes from.
#[derive(Clone, Debug)]
pub enum Source {
    File(PathBuf),
    /// XML text; `name` stands for the file in messages and anchors relative paths.
    Text {
        xml: String,
        name: String,
    },
}

/// The built-in Xenopeltis scene (`scenes/xenopeltis.xml`, compiled into the library).
pub fn xenopeltis() -> Source {
    Source::Text {
        xml: XENOPELTIS_XML.to_string(),
        name: "xenopeltis.xml".into(),
    }
}

impl Source {
    fn tree(&self, defines: &[(String, String)]) -> Result<Node, Error> {
        let (root, _) = match self {
            Source::File(p) => mitsuba::load_file(p, defines)?,
            Source::Text { xml, name } => mitsuba::load_str(xml, Path::new(name), defines)?,
        };
        Ok(root)
    }

    fn file_name(&self) -> String {
        match self {
            Source::File(p) => p.file_name().unwrap_or_default().to_string_lossy().into(),
            Source::Text { name, .. } => name.clone(),
        }
    }
}

/// A loader warning with its location.
pub struct Warning(pub Located);

/// A built scene and its identity (for the EXR header).
pub struct LoadedScene {
    scene: Scene,
    identity: SceneIdentity,
    /// The scene's own `adaptive` (its sampler's), which a render's choice overrides once.
    adaptive: bool,
}

/// Loads and builds a scene; `defines` are Mitsuba's `-D name=value`.
pub fn load(
    source: &Source,
    defines: &[(String, String)],
) -> Result<(LoadedScene, Vec<Warning>), Error> {
    let opts = LoadOptions {
        defines: defines.to_vec(),
        ..Default::default()
    };
    let (scene, warnings) = match source {
        Source::File(p) => load_scene(p, &opts)?,
        Source::Text { xml, name } => load_scene_str(xml, Path::new(name), &opts)?,
    };
    let identity = SceneIdentity::of(&source.tree(defines)?, &source.file_name(), defines);
    let warnings = warnings
        .into_iter()
        .map(|w| {
            Warning(Located {
                file: w.loc.file.display().to_string(),
                line: w.loc.line,
                column: w.loc.col,
                message: w.message,
            })
        })
        .collect();
    let adaptive = scene.sampler.adaptive;
    Ok((
        LoadedScene {
            scene,
            identity,
            adaptive,
        },
        warnings,
    ))
}

impl LoadedScene {
    /// Image width and height in pixels.
    pub fn resolution(&self) -> (u32, u32) {
        (self.scene.width, self.scene.height)
    }
    /// The sampler's samples per pixel.
    pub fn spp(&self) -> u32 {
        self.scene.sampler.spp
    }
    /// Readable name: file name and `-D` values.
    pub fn name(&self) -> &str {
        &self.identity.name
    }
    /// `ophis.scene_hash` of renders of this scene.
    pub fn hash_hex(&self) -> String {
        self.identity.hash_hex()
    }
    /// Sets the seed of the sample sequences for the next render.
    pub fn set_seed(&mut self, seed: u64) {
        self.scene.sampler.seed = seed;
    }
    /// Sets adaptive sampling on or off for the next render; `None`: the scene's own choice.
    pub fn set_adaptive(&mut self, adaptive: Option<bool>) {
        self.scene.sampler.adaptive = adaptive.unwrap_or(self.adaptive);
    }
}

/// Samples done and to do, updated by the render's workers, read by the waiting thread.
#[derive(Default)]
pub struct Counter {
    pub done: AtomicU64,
    pub total: AtomicU64,
}

impl Progress for Counter {
    fn update(&self, done: u64, total: u64) {
        self.total.store(total, Ordering::Relaxed);
        self.done.fetch_max(done, Ordering::Relaxed);
    }
}

/// A finished or stopped render.
pub struct Rendered {
    pub width: usize,
    pub height: usize,
    /// Names of the channels per pixel, in order (R, G, B; AOVs would follow).
    pub channels: Vec<String>,
    /// Pixels × channels, row-major, top row first.
    pub data: Vec<f32>,
    /// The EXR header `ophis render` writes: counts, seed, scene identity.
    pub metadata: Vec<(String, String)>,
    pub spp_complete: u32,
    pub samples: u64,
    pub seconds: f64,
    /// Stopped before the target spp (cancelled).
    pub stopped_early: bool,
}

/// Renders `spp` samples per pixel (the scene's own without it) on `threads` workers (all
/// cores without it), until done or `cancel` is set; tiles in flight then finish and the image
/// holds every sample taken, each pixel normalised by its own count.
pub fn render(
    s: &LoadedScene,
    spp: Option<u32>,
    threads: Option<usize>,
    cancel: &AtomicBool,
    progress: &Counter,
) -> Result<Rendered, Error> {
    let spp = spp.unwrap_or(s.scene.sampler.spp);
    if spp == 0 {
        return Err(Error::Value("spp must be at least 1".into()));
    }
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        if n == 0 {
            return Err(Error::Value("threads must be at least 1".into()));
        }
        pool = pool.num_threads(n);
    }
    let pool = pool
        .build()
        .map_err(|e| Error::Value(format!("cannot start {threads:?} threads: {e}")))?;
    let scene = &s.scene;
    let mut film = Film::new(scene.width, scene.height);
    let opts = RenderOptions {
        spp,
        time_limit: None,
        strategy: PathStrategy::Mis,
        engine: ophis::render::Engine::Auto,
    };
    let ctl = RenderControl {
        cancel,
        progress,
        checkpoint: None,
        tile_order: TileOrder::RowMajor,
    };
    let stats = pool.install(|| render_with(scene, &mut film, 0, &opts, &ctl));
    let metadata = render_metadata(&film, stats.spp_complete, scene.sampler.seed, &s.identity);
    // The `aov` integrator's channels follow R, G, B in each pixel, named as in the EXR that
    // `ophis render` writes; Python reshapes by the number of names.
    let aovs = film.aov_images();
    let mut channels: Vec<String> = vec!["R".into(), "G".into(), "B".into()];
    channels.extend(aovs.iter().map(|(n, _)| n.clone()));
    let rgb = film.to_linear_srgb();
    let mut data = Vec::with_capacity(rgb.len() * channels.len());
    for (i, p) in rgb.iter().enumerate() {
        data.extend_from_slice(p);
        data.extend(aovs.iter().map(|(_, a)| a[i]));
    }
    Ok(Rendered {
        width: film.width as usize,
        height: film.height as usize,
        channels,
        data,
        metadata,
        spp_complete: stats.spp_complete,
        samples: film.total_weight() as u64,
        seconds: stats.seconds,
        stopped_early: stats.stopped_early,
    })
}

/// Writes RGB pixels (row-major, 3 floats each) as EXR (with `metadata` in its header and the
/// named `extra` channels, e.g. AOVs, beside R, G, B) or PNG (sRGB-encoded, 8 bit, RGB only),
/// chosen by the extension.
pub fn write_image(
    path: &Path,
    width: usize,
    height: usize,
    rgb: &[f32],
    extra: &[(String, Vec<f32>)],
    metadata: &[(String, String)],
) -> Result<(), Error> {
    let image = RgbImage {
        width,
        height,
        data: rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect(),
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("exr") if extra.is_empty() => write_exr(path, &image, metadata)?,
        Some("exr") => {
            // Marked as `ophis render` marks AOV files, so that `ophis merge` refuses them.
            let names: Vec<&str> = extra.iter().map(|(n, _)| n.as_str()).collect();
            let mut meta = metadata.to_vec();
            meta.push((KEY_AOVS.to_string(), names.join(",")));
            write_exr_channels(path, &image, extra, &meta)?
        }
        Some("png") => write_png(path, &image)?,
        _ => {
            return Err(Error::Value(format!(
                "{}: the file name must end in .exr or .png",
                path.display()
            )))
        }
    }
    Ok(())
}

/// An image read back: RGB pixels, the EXR header's text attributes, and the samples of each
/// pixel when the header has `ophis.tile_spp`.
pub struct ReadImage {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<f32>,
    pub metadata: Vec<(String, String)>,
    pub pixel_spp: Option<Vec<u64>>,
}

/// Reads an EXR, HDR or PNG image (by its signature); EXR headers come with it.
pub fn read(path: &Path) -> Result<ReadImage, Error> {
    let image = read_image(path)?;
    let metadata = read_exr_metadata(path).unwrap_or_default();
    let pixel_spp =
        match metadata.iter().find(|(k, _)| k == KEY_TILE_SPP) {
            Some((_, v)) => Some(decode_tile_spp(v, image.width, image.height).map_err(|e| {
                Error::Value(format!("{}: bad {KEY_TILE_SPP}: {e}", path.display()))
            })?),
            None => None,
        };
    Ok(ReadImage {
        width: image.width,
        height: image.height,
        rgb: image.data.into_iter().flatten().collect(),
        metadata,
        pixel_spp,
    })
}

/// A single film over a base: the same description as `ophis thinfilm`'s arguments.
pub struct FilmArgs<'a> {
    pub film_ior: &'a str,
    pub thickness_nm: f64,
    /// A stack in `ophis thinfilm --stack` syntax (outside in, `INDEX:NM`, groups
    /// `(…)xN`); replaces `film_ior` and `thickness_nm` when given.
    pub stack: Option<&'a str>,
    pub ext_ior: &'a str,
    /// A dielectric base (index or name), or a metal base n + ik.
    pub int_ior: Option<&'a str>,
    pub int_nk: Option<(f64, f64)>,
}

/// R, T, Rs, Rp per (wavelength, angle), wavelengths outer; and linear sRGB of reflected D65
/// per angle.
pub struct FilmTable {
    pub r: Vec<f64>,
    pub t: Vec<f64>,
    pub r_s: Vec<f64>,
    pub r_p: Vec<f64>,
    pub rgb: Vec<f64>,
}

/// Reflectance table and colours of a film; errors name the argument (Python's spelling).
pub fn thinfilm(a: &FilmArgs, wavelengths: &[f64], angles: &[f64]) -> Result<FilmTable, Error> {
    let v = Error::Value;
    if !(a.thickness_nm >= 0.0 && a.thickness_nm.is_finite()) {
        return Err(v(format!(
            "thickness: the film thickness must be a finite number ≥ 0 nm, got {}",
            a.thickness_nm
        )));
    }
    if let Some(x) = angles.iter().find(|x| !(0.0..=90.0).contains(*x)) {
        return Err(v(format!("angles: {x} is outside 0–90 degrees")));
    }
    if let Some(l) = wavelengths.iter().find(|l| !(**l > 0.0 && l.is_finite())) {
        return Err(v(format!(
            "wavelengths: {l} nm is not a positive wavelength"
        )));
    }
    let base = match (a.int_ior, a.int_nk) {
        (Some(_), Some(_)) => {
            return Err(v(
                "give int_ior (a dielectric base) or int_eta and int_k (a metal \
                 base), not both"
                    .into(),
            ))
        }
        (Some(s), None) => parse_index("int_ior", s).map_err(v)?,
        (None, Some((n, k))) => {
            if !(n > 0.0 && n.is_finite()) {
                return Err(v(format!("int_eta: must be positive, got {n}")));
            }
            if !(k >= 0.0 && k.is_finite()) {
                return Err(v(format!("int_k: must be ≥ 0, got {k}")));
            }
            Ior::complex(n, k).map_err(|e| v(format!("int_eta, int_k: {e}")))?
        }
        (None, None) => Ior::Real(1.0),
    };
    let ext = parse_index("ext_ior", a.ext_ior).map_err(v)?;
    let stack = match a.stack {
        Some(spec) => {
            let items = parse_items(spec).map_err(|e| v(format!("stack: {e}")))?;
            FilmStack::new(ext, items, base).map_err(|e| v(format!("stack: {e}")))?
        }
        None => {
            let film = parse_index("film_ior", a.film_ior).map_err(v)?;
            FilmStack::film(ext, film, a.thickness_nm, base).map_err(v)?
        }
    };
    let n = wavelengths.len() * angles.len();
    let mut t = FilmTable {
        r: Vec::with_capacity(n),
        t: Vec::with_capacity(n),
        r_s: Vec::with_capacity(n),
        r_p: Vec::with_capacity(n),
        rgb: Vec::with_capacity(3 * angles.len()),
    };
    for &l in wavelengths {
        for &ang in angles {
            let rt = rt_deg(&stack, ang, l, false);
            t.r.push(rt.r());
            t.t.push(rt.t());
            t.r_s.push(rt.r_s);
            t.r_p.push(rt.r_p);
        }
    }
    for &ang in angles {
        t.rgb.extend(stack_rgb(&stack, ang, false));
    }
    Ok(t)
}

/// What `bsdf_estimate` estimates (angles in degrees, as `ophis bsdf`).
pub enum BsdfQuery {
    Albedo {
        theta_i: f32,
    },
    Eval {
        theta_i: f32,
        theta_o: f32,
        phi_o: f32,
    },
}

/// (mean, standard error) of a BSDF's albedo or f·cos, per wavelength, or as linear sRGB under
/// D65 (three values) without wavelengths: the numbers `ophis bsdf` prints for the same
/// arguments and seed.
pub fn bsdf_estimate(
    source: &Source,
    defines: &[(String, String)],
    id: &str,
    q: BsdfQuery,
    wavelengths: Option<&[f32]>,
    samples: usize,
    seed: u64,
) -> Result<Vec<(f64, f64)>, Error> {
    if samples < 2 {
        return Err(Error::Value("samples must be at least 2".into()));
    }
    let root = source.tree(defines)?;
    let node = find_bsdf(&root, id).ok_or_else(|| {
        Error::Value(format!(
            "no <bsdf> with id '{id}' in {} (ids: {})",
            source.file_name(),
            bsdf_ids(&root).join(", ")
        ))
    })?;
    let material = build_material(node, &mut Vec::new())?;
    let q = match q {
        BsdfQuery::Albedo { theta_i } => Quantity::Albedo { theta_i },
        BsdfQuery::Eval {
            theta_i,
            theta_o,
            phi_o,
        } => Quantity::Eval {
            theta_i,
            theta_o,
            phi_o,
        },
    };
    Ok(match wavelengths {
        None => linear_srgb(&material, q, samples, seed)
            .iter()
            .map(|e| (e.mean, e.std_err))
            .collect(),
        Some(ls) => {
            if let Some(l) = ls.iter().find(|l| !(**l > 0.0 && l.is_finite())) {
                return Err(Error::Value(format!(
                    "wavelengths: {l} nm is not a positive wavelength"
                )));
            }
            ls.iter()
                .map(|&l| {
                    let e = at_wavelength(&material, q, l, samples, seed);
                    (e.mean, e.std_err)
                })
                .collect()
        }
    })
}
