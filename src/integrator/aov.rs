//! `aov`: arbitrary output variables — what the camera ray sees first (depth, position, normals,
//! UV, which shape, the surface's albedo) written as extra EXR channels beside the image, for
//! masks in scripts and as the auxiliary inputs of a denoiser (Mitsuba 3's `aov` integrator).
//!
//! ```xml
//! <integrator type="aov">
//!     <string name="aovs" value="dd.y:depth,nn:sh_normal,id:shape_index"/>
//!     <integrator type="path" name="my_image"/>
//! </integrator>
//! ```
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `aovs` | string | required | — | comma-separated `name:type` pairs (types below) |
//! | `(nested)` | integrator | — | — | at most one `path` (or `direct`): the colour image (R, G, B), also written as `NAME.R`, `.G`, `.B`, `.A` when it has a `name` |
//!
//! Without a nested integrator the image is black and only the AOVs carry information.
//!
//! | type          | channels        | value at the camera ray's first hit (0 where it escapes)      |
//! |---------------|-----------------|----------------------------------------------------------------|
//! | `depth`       | `name.T`        | ray distance from the camera's near plane (as Mitsuba's `si.t`) |
//! | `position`    | `.X .Y .Z`      | world-space hit point                                          |
//! | `uv`          | `.U .V`         | texture coordinates                                            |
//! | `geo_normal`  | `.X .Y .Z`      | geometric normal (facing the shape's outside)                  |
//! | `sh_normal`   | `.X .Y .Z`      | interpolated shading normal (before bump or normal maps, as Mitsuba) |
//! | `dp_du`, `dp_dv` | `.X .Y .Z`   | position derivatives                                           |
//! | `prim_index`  | `name.I`        | triangle index within its shape                                |
//! | `shape_index` | `name.I`        | 1 + the shape's position in the scene (declaration order; a `snake` counts one shape per part), 0 for none |
//! | `albedo`      | `.R .G .B`      | directional albedo ρ(ωo) of the surface, linear sRGB           |
//!
//! Each channel is averaged over the pixel's samples like the image (through the same filter),
//! so values at edges and in defocused regions are mixtures: an integer AOV is exact only where
//! every sample saw the same surface (Mitsuba warns the same). `ophis render` writes the shape
//! labels behind `shape_index` into the EXR header (`ophis.shapes`, `index=label;…`).
//!
//! `albedo` differs from Mitsuba's, which returns each BSDF's diffuse reflectance (undefined for
//! ophis's film and layered materials): here it is ∫ f·|cos θ| dωi, estimated with one BSDF
//! sample at each of eight stratified sets of four wavelengths per camera sample, from a random
//! stream of its own (so the image does not change when AOVs are added), converted from the
//! spectrum under D65 — exact for `diffuse` up to the spectral quadrature (cosine sampling has
//! no variance), and for glass or a film the sum of reflection and transmission.
//! `duv_dx`, `duv_dy` (no ray differentials yet) and `boundary_test` are refused.

use crate::bsdf::{Bsdf, Material, TransportMode};
use crate::film::spectrum_to_xyz;
use crate::math::rng::mix64;
use crate::math::{Pcg32, Ray};
use crate::plugin::{declare, registry, Args, DefaultValue, Param, SceneError, Tag, Ty};
use crate::scene::{IntegratorSettings, Scene};
use crate::spectrum::{cie, SampledSpectrum, SampledWavelengths};
use crate::texture::TexCoord;

/// What an AOV records.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AovKind {
    Albedo,
    Depth,
    Position,
    Uv,
    GeoNormal,
    ShNormal,
    DpDu,
    DpDv,
    PrimIndex,
    ShapeIndex,
}

impl AovKind {
    /// Mitsuba's name of the type.
    pub(crate) fn from_name(s: &str) -> Option<AovKind> {
        Some(match s {
            "albedo" => AovKind::Albedo,
            "depth" => AovKind::Depth,
            "position" => AovKind::Position,
            "uv" => AovKind::Uv,
            "geo_normal" => AovKind::GeoNormal,
            "sh_normal" => AovKind::ShNormal,
            "dp_du" => AovKind::DpDu,
            "dp_dv" => AovKind::DpDv,
            "prim_index" => AovKind::PrimIndex,
            "shape_index" => AovKind::ShapeIndex,
            _ => return None,
        })
    }

    /// Channel suffixes, in Mitsuba's order.
    fn suffixes(self) -> &'static [&'static str] {
        match self {
            AovKind::Albedo => &["R", "G", "B"],
            AovKind::Depth => &["T"],
            AovKind::Uv => &["U", "V"],
            AovKind::PrimIndex | AovKind::ShapeIndex => &["I"],
            _ => &["X", "Y", "Z"],
        }
    }
}

/// One requested AOV.
#[derive(Clone, Debug, PartialEq)]
pub struct Aov {
    pub name: String,
    pub kind: AovKind,
}

/// The `aov` integrator's settings (the nested path tracer's are the scene's
/// [`crate::scene::IntegratorSettings`]).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct AovSettings {
    pub aovs: Vec<Aov>,
    /// Whether a nested integrator renders the colour image.
    pub has_image: bool,
    /// The nested integrator's `name`, if it has one (its RGBA copy is written under it).
    pub image_name: Option<String>,
}

declare!(PLUGIN: IntegratorSettings = Integrator "aov" []
    "extra channels beside the image: depth, normals, UV, shape index, albedo, …"
    [&[
        Param::new("aovs", Ty::String, DefaultValue::Required)
            .doc("comma-separated `name:type` pairs (types below)"),
        Param::new("(nested)", Ty::Object(Tag::Integrator), DefaultValue::None).doc(
            "at most one `path` (or `direct`): the colour image (R, G, B), also written as \
             `NAME.R`, `.G`, `.B`, `.A` when it has a `name`",
        ),
    ]] load);

fn load(a: &mut Args, _: ()) -> Result<IntegratorSettings, SceneError> {
    let spec = a.string("aovs")?;
    let aovs = parse_aovs(&spec).map_err(|e| a.error("aovs", e))?;
    let nested: Vec<_> = a
        .node()
        .children
        .iter()
        .filter(|c| c.node.tag == Tag::Integrator)
        .collect();
    if let Some(extra) = nested.get(1) {
        return Err(SceneError::at(
            &extra.node.loc,
            "ophis's aov integrator takes at most one nested integrator",
        ));
    }
    let (mut settings, has_image, image_name) = match nested.first() {
        Some(c) if c.node.plugin == "aov" => {
            return Err(SceneError::at(
                &c.node.loc,
                "an aov integrator cannot nest another",
            ))
        }
        Some(c) => (
            registry::integrator(&c.node, a.warnings())?,
            true,
            c.name.clone(),
        ),
        None => (IntegratorSettings::default(), false, None),
    };
    settings.aov = Some(AovSettings {
        aovs,
        has_image,
        image_name,
    });
    Ok(settings)
}

/// Parses Mitsuba's `aovs` string: `name:type` pairs separated by commas.
pub(crate) fn parse_aovs(spec: &str) -> Result<Vec<Aov>, String> {
    let mut out: Vec<Aov> = Vec::new();
    for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let Some((name, kind)) = item.split_once(':') else {
            return Err(format!("'{item}' is not a name:type pair"));
        };
        let (name, kind) = (name.trim(), kind.trim());
        if name.is_empty() {
            return Err(format!("'{item}' has an empty name"));
        }
        let kind = match (AovKind::from_name(kind), kind) {
            (Some(k), _) => k,
            (None, "duv_dx" | "duv_dy" | "boundary_test") => {
                return Err(format!(
                    "AOV type '{kind}' is not supported by ophis (it needs ray differentials or \
                     boundary tests)"
                ))
            }
            (None, _) => {
                return Err(format!(
                    "unknown AOV type '{kind}' in '{item}'; expected one of albedo, depth, \
                     position, uv, geo_normal, sh_normal, dp_du, dp_dv, prim_index, shape_index"
                ))
            }
        };
        if out.iter().any(|a| a.name == name) {
            return Err(format!("AOV name '{name}' is used twice"));
        }
        out.push(Aov {
            name: name.to_string(),
            kind,
        });
    }
    if out.is_empty() {
        return Err("no AOVs given".into());
    }
    Ok(out)
}

impl AovSettings {
    /// Names of the accumulated channels, in order.
    pub fn channel_names(&self) -> Vec<String> {
        self.aovs
            .iter()
            .flat_map(|a| a.kind.suffixes().iter().map(|s| format!("{}.{s}", a.name)))
            .collect()
    }

    /// Number of accumulated channels.
    pub fn channels(&self) -> usize {
        self.aovs.iter().map(|a| a.kind.suffixes().len()).sum()
    }

    /// Adds one camera sample's AOVs to `out` (one value per channel). `key` identifies the
    /// pixel sample (it seeds the albedo estimate's own random stream).
    pub(crate) fn accumulate(&self, scene: &Scene, ray: &Ray, key: u64, out: &mut [f64]) {
        let hit = scene.intersect(ray).map(|(_, si)| si);
        let mut k = 0;
        let mut put = |vals: &[f32]| {
            for v in vals {
                out[k] += *v as f64;
                k += 1;
            }
        };
        let Some(si) = hit else {
            return;
        };
        for a in &self.aovs {
            match a.kind {
                AovKind::Depth => put(&[si.t]),
                AovKind::Position => put(&si.p.to_array()),
                AovKind::Uv => put(&si.uv.to_array()),
                AovKind::GeoNormal => put(&si.ng.to_array()),
                AovKind::ShNormal => put(&si.ns.to_array()),
                AovKind::DpDu => put(&si.dpdu.to_array()),
                AovKind::DpDv => put(&si.dpdv.to_array()),
                AovKind::PrimIndex => put(&[si.prim as f32]),
                AovKind::ShapeIndex => put(&[(si.shape + 1) as f32]),
                AovKind::Albedo => put(&albedo(scene, ray, &si, key)),
            }
        }
    }
}

/// Wavelength strata of the albedo estimate (each with the path's four hero wavelengths).
const ALBEDO_STRATA: usize = 8;

/// Estimate of the directional albedo at a camera hit, as linear sRGB under D65: one BSDF
/// sample at each of `ALBEDO_STRATA` stratified sets of four wavelengths, so that the colour
/// conversion sees 32 wavelengths spread over the spectrum (four would leave it as noisy as
/// the image's own colour).
fn albedo(scene: &Scene, ray: &Ray, si: &crate::shape::SurfaceInteraction, key: u64) -> [f32; 3] {
    let material = &scene.materials[scene.shape_material[si.shape as usize] as usize];
    if matches!(material, Material::Null) {
        return [0.0; 3];
    }
    let wo = -ray.d;
    let tc = TexCoord { uv: si.uv, p: si.p };
    let frame = material.shading_frame(si, wo, scene.camera.footprint(scene.height, si.t));
    let mut rng = Pcg32::new(mix64(key ^ 0x5eed_a1be_d000_0000), 0xa0f);
    let offset = rng.next_f32();
    let mut xyz = [0.0f32; 3];
    for k in 0..ALBEDO_STRATA {
        let wl = SampledWavelengths::sample_visible((k as f32 + offset) / ALBEDO_STRATA as f32);
        // The layered walk's random numbers come from this seed, one per stratum.
        let (bxdf, two_sided) = material.eval(
            &tc,
            &wl,
            si.ng.dot(wo) >= 0.0,
            mix64(((rng.next_u32() as u64) << 32) | k as u64),
        );
        let bsdf = Bsdf {
            frame,
            bxdf,
            two_sided,
        };
        let (uc, u) = (rng.next_f32(), rng.next_vec2());
        let rho = match bsdf.sample_f(wo, uc, u, TransportMode::Radiance) {
            Some(bs) if bs.pdf > 0.0 => bs.f * (bs.wi.dot(bsdf.frame.n).abs() / bs.pdf),
            _ => SampledSpectrum::ZERO,
        };
        if !rho.is_finite() {
            continue;
        }
        let mut lit = rho;
        for i in 0..crate::spectrum::N {
            lit[i] *= cie::d65(wl.lambda[i]);
        }
        let c = spectrum_to_xyz(&lit, &wl);
        for (a, b) in xyz.iter_mut().zip(c) {
            *a += b / ALBEDO_STRATA as f32;
        }
    }
    cie::xyz_to_linear_srgb(xyz)
}

/// A key for one pixel sample (for [`AovSettings::accumulate`]).
#[inline]
pub(crate) fn sample_key(seed: u64, x: u32, y: u32, index: u32) -> u64 {
    mix64(seed ^ mix64(((y as u64) << 32) | x as u64) ^ ((index as u64) << 17))
}

#[cfg(test)]
#[path = "aov_tests.rs"]
mod tests;
