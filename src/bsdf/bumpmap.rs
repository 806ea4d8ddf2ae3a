//! `bumpmap` and `normalmap`: wrappers that change the shading frame of a nested BSDF.
//!
//! Bump mapping (Blinn, "Simulation of Wrinkled Surfaces", SIGGRAPH 1978): the surface is
//! displaced along its normal by `scale`·h(u, v); the displaced tangents are
//! ∂p'/∂u ≈ ∂p/∂u + `scale`·∂h/∂u·n and likewise for v (the term h·∂n/∂u is dropped, as Blinn
//! does: it is of relative size `scale`·h/radius of curvature). The tangents are first projected
//! into the plane of the shading normal, so interpolated mesh normals keep working; the new normal
//! is their cross product, turned to the side of the old one (which makes the result right for
//! either handedness of the UV map). `scale` is in world units per unit of height, as in
//! Mitsuba 3's `bumpmap`.
//!
//! When the height texture is a `scales` pattern (or a `per_scale` over one) with a non-zero
//! `tilt_degrees`, each scale's normal is then rotated by its own random tilt about an axis in
//! the tangent plane — the scale-by-scale sparkle of real skin.
//!
//! `normalmap` (its plugin file is `normalmap.rs`) takes its normal in tangent space (x along
//! ∂p/∂u, y along ∂p/∂v, z the shading normal), as Mitsuba 3's does, from a `bitmap` or from
//! a `scales` texture's relief (its slope measured in cells, times `strength`).
//!
//! Visible side: a perturbed normal can face away from the viewer while the surface faces it,
//! which shows as black fringes. The normal is then bent towards the viewer (a multiple of wo is
//! added) until it is just on the viewer's side, the side of the geometric normal.
//!
//! Footprint: without ray differentials, the width a pixel covers at a hit is estimated as the
//! camera's pixel angle times the path length to the hit, divided by |cos θ| (at least 0.05); the
//! height texture fades detail finer than that.
//!
//! ## Parameters
//!
//! | parameter | type | default | unit | meaning |
//! |---|---|---|---|---|
//! | `(nested texture)` | texture | required | — | the height h (a float texture: `scales`, `bitmap`, …) |
//! | `scale` | float | 1.0 | world units | displacement per unit of height |
//! | `(nested bsdf)` | bsdf | `diffuse` | — | the material being bumped |
//!
//! Limits: piecewise-constant textures (`checkerboard`, `per_scale`) have no slope and do not
//! bump; the displaced surface is not traced (silhouettes stay smooth), as in any bump map.

use super::material::Material;
use crate::math::{Frame, Vec2, Vec3};
use crate::plugin::{declare, Args, DefaultValue, Param, SceneError, Tag, Ty};
use crate::shape::SurfaceInteraction;
use crate::texture::{FloatTexture, NormalSource, Scales, TexCoord, Texture, Want};

declare!(PLUGIN: Material = Bsdf "bumpmap" []
    "bump mapping: a nested BSDF with its normal displaced by a height texture"
    [&[
            Param::new("(nested texture)", Ty::Texture, DefaultValue::Required)
                .doc("the height h (a float texture: `scales`, `bitmap`, …)"),
            Param::float("scale", 1.0)
                .unit("world units")
                .doc("displacement per unit of height"),
            Param::new(
                "(nested bsdf)",
                Ty::Bsdf,
                DefaultValue::Derived("`diffuse`"),
            )
            .doc("the material being bumped"),
        ]] load);

/// The single nested BSDF of a wrapper (Mitsuba's default diffuse when absent).
pub(crate) fn nested_bsdf(a: &mut Args) -> Result<Material, SceneError> {
    match a.children(Tag::Bsdf).as_slice() {
        [] => Ok(Material::default_diffuse()),
        [b] => a.bsdf(b),
        more => Err(SceneError::at(
            &a.node().loc,
            format!(
                "{} takes one nested BSDF, found {}",
                a.describe(),
                more.len()
            ),
        )),
    }
}

fn load(a: &mut Args, _: ()) -> Result<Material, SceneError> {
    let textures = a.children(Tag::Texture);
    let [tex] = textures.as_slice() else {
        return Err(SceneError::at(
            &a.node().loc,
            format!(
                "bumpmap needs exactly one nested height texture, found {}",
                textures.len()
            ),
        ));
    };
    let Texture::Float(height) = a.texture_node(tex, Want::Float)? else {
        return Err(SceneError::at(
            &tex.loc,
            "bumpmap: the height must be a float texture",
        ));
    };
    Ok(Material::BumpMap {
        height,
        scale: a.float("scale")?,
        inner: Box::new(nested_bsdf(a)?),
    })
}

/// The normal source of a `normalmap` from its nested texture.
pub(crate) fn normal_source(a: &mut Args) -> Result<NormalSource, SceneError> {
    let textures = a.children(Tag::Texture);
    let [tex] = textures.as_slice() else {
        return Err(SceneError::at(
            &a.node().loc,
            "normalmap needs exactly one nested normal texture",
        ));
    };
    match a.texture_node(tex, Want::Normals)? {
        Texture::Normals(n) => Ok(n),
        _ => Err(SceneError::at(
            &tex.loc,
            format!(
                "normalmap: texture '{}' cannot supply normals (use a 'bitmap' or a 'scales' \
                 texture)",
                tex.plugin
            ),
        )),
    }
}

/// Smallest cosine the visible-side correction leaves between the normal and wo.
const MIN_VISIBLE_COS: f32 = 0.01;

/// Tangents projected into the plane of `n`.
#[inline]
fn project(n: Vec3, v: Vec3) -> Vec3 {
    v - n * n.dot(v)
}

/// The bumped normal and ∂p'/∂u for shading normal `n`, tangents `dpdu`/`dpdv`, height
/// gradient `grad` (per unit u, v) and displacement `scale`. Returns `n` unchanged where the
/// tangents are degenerate.
pub(crate) fn bump_normal(n: Vec3, dpdu: Vec3, dpdv: Vec3, grad: Vec2, scale: f32) -> (Vec3, Vec3) {
    let (tu, tv) = (project(n, dpdu), project(n, dpdv));
    let pu = tu + n * (scale * grad.x);
    let pv = tv + n * (scale * grad.y);
    let c = pu.cross(pv);
    let len = c.length();
    if len.is_nan() || len <= 1e-20 || !len.is_finite() {
        return (n, dpdu);
    }
    let m = c / len;
    (if m.dot(n) < 0.0 { -m } else { m }, pu)
}

/// Rotates `n` by `angle` about the tangent-plane axis at azimuth `phi` from `s`.
pub fn tilt(n: Vec3, s: Vec3, angle: f32, phi: f32) -> Vec3 {
    if angle == 0.0 {
        return n;
    }
    let f = Frame::from_normal_tangent(n, s);
    let axis = f.s * phi.cos() + f.t * phi.sin();
    let (sa, ca) = angle.sin_cos();
    // Rodrigues' rotation; axis ⟂ n, so the axis·n term vanishes.
    (n * ca + axis.cross(n) * sa).normalize()
}

/// Bends `n` towards `wo` so that it lies on the same side of `wo` as the geometric normal
/// `ng` (with a margin); unchanged when it already does.
pub(crate) fn keep_visible(n: Vec3, ng: Vec3, wo: Vec3) -> Vec3 {
    let side = if ng.dot(wo) >= 0.0 { 1.0 } else { -1.0 };
    let c = n.dot(wo) * side;
    if c >= MIN_VISIBLE_COS {
        return n;
    }
    let m = n + wo * (side * (MIN_VISIBLE_COS * 2.0) - n.dot(wo));
    let m = m.normalize_or_zero();
    if m == Vec3::ZERO {
        ng * side
    } else {
        m
    }
}

/// Width a pixel covers on the surface in UV units, per axis, for a world-space footprint
/// `width` seen at cosine `cos` to the normal.
pub(crate) fn uv_footprint(si: &SurfaceInteraction, width: f32, cos: f32) -> Vec2 {
    let w = width / cos.abs().max(0.05);
    let lu = si.dpdu.length();
    let lv = si.dpdv.length();
    let f = |l: f32| if l > 0.0 { w / l } else { 0.0 };
    Vec2::new(f(lu), f(lv))
}

/// The normal of a `scales` relief in tangent space: slope in cells, times `strength`.
pub(crate) fn scales_tangent_normal(
    cells: &Scales,
    uv: Vec2,
    footprint: Vec2,
    strength: f32,
) -> Vec3 {
    let g = cells.gradient(uv, cells.cells_across(footprint));
    Vec3::new(
        -strength * g.x / cells.scale_u,
        -strength * g.y / cells.scale_v,
        1.0,
    )
    .normalize()
}

impl Material {
    /// The shading frame at a hit seen from `wo`, with a world-space pixel footprint `width`:
    /// the shape's own (shading normal, ∂p/∂u) unless a `bumpmap`/`normalmap` changes it.
    pub(crate) fn shading_frame(&self, si: &SurfaceInteraction, wo: Vec3, width: f32) -> Frame {
        match self.perturbed_normal(si, wo, width, si.ng.dot(wo) >= 0.0) {
            Some((n, s)) => Frame::from_normal_tangent(keep_visible(n, si.ng, wo), s),
            None => Frame::from_normal_tangent(si.ns, si.dpdu),
        }
    }

    /// The perturbed (normal, tangent), or `None` for materials that keep the shape's.
    fn perturbed_normal(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        width: f32,
        front_side: bool,
    ) -> Option<(Vec3, Vec3)> {
        let tc = TexCoord { uv: si.uv, p: si.p };
        let fp = || uv_footprint(si, width, si.ns.dot(wo));
        // A map over another bump or normal map perturbs the inner one's frame.
        let inner_frame = |inner: &Material| {
            inner
                .perturbed_normal(si, wo, width, front_side)
                .unwrap_or((si.ns, si.dpdu))
        };
        match self {
            Material::BumpMap {
                height,
                scale,
                inner,
            } => {
                let (n0, s0) = inner_frame(inner);
                let grad = height.gradient(&tc, fp());
                let (n, s) = bump_normal(n0, s0, si.dpdv, grad, *scale);
                Some((apply_cell_tilt(height, n, s, si.uv), s))
            }
            Material::NormalMap {
                source,
                strength,
                inner,
            } => {
                let (n0, s0) = inner_frame(inner);
                let local = match source {
                    NormalSource::Scales(cells) => {
                        scales_tangent_normal(cells, si.uv, fp(), *strength)
                    }
                    // Mitsuba's convention: the texel's RGB in [0, 1] encodes n = 2·rgb − 1.
                    NormalSource::Bitmap(b) => {
                        let c = b.rgb(si.uv);
                        let n = Vec3::new(2.0 * c[0] - 1.0, 2.0 * c[1] - 1.0, 2.0 * c[2] - 1.0);
                        let n = Vec3::new(n.x * strength, n.y * strength, n.z);
                        if n.z > 0.0 && n.is_finite() {
                            n.normalize()
                        } else {
                            Vec3::Z
                        }
                    }
                };
                let f = Frame::from_normal_tangent(n0, s0);
                // y follows ∂p/∂v, whichever handedness the UV map has.
                let t = if f.t.dot(si.dpdv) < 0.0 { -f.t } else { f.t };
                let n = (f.s * local.x + t * local.y + n0 * local.z).normalize();
                match source {
                    NormalSource::Scales(cells) => {
                        let (a, phi) = cells.tilt_at(si.uv);
                        Some((tilt(n, f.s, a, phi), f.s))
                    }
                    NormalSource::Bitmap(_) => Some((n, f.s)),
                }
            }
            Material::TwoSided { front, back } => {
                let m = match back {
                    Some(b) if !front_side => b,
                    _ => front,
                };
                m.perturbed_normal(si, wo, width, true)
            }
            _ => None,
        }
    }
}

/// The per-scale tilt of a `scales`-driven bump.
fn apply_cell_tilt(height: &FloatTexture, n: Vec3, s: Vec3, uv: Vec2) -> Vec3 {
    match height.cells() {
        Some(c) if c.tilt > 0.0 => {
            let (a, phi) = c.tilt_at(uv);
            tilt(n, s, a, phi)
        }
        _ => n,
    }
}

#[cfg(test)]
#[path = "bumpmap_tests.rs"]
mod tests;
