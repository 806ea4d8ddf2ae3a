//! Triangle meshes, stored in world space.
//!
//! | XML name       | type      | default  | meaning                                               |
//! |----------------|-----------|----------|-------------------------------------------------------|
//! | `filename`     | string    | —        | OBJ or PLY file (`obj` / `ply` plugins, see `obj.rs`, `ply.rs`) |
//! | `to_world`     | transform | identity | any invertible affine map                             |
//! | `flip_normals` | boolean   | false    | negate geometric and shading normals                  |
//! | `face_normals` | boolean   | false    | ignore vertex normals (flat shading)                  |
//!
//! The geometric normal follows the winding: counter-clockwise seen from the front is the front
//! (as in Mitsuba). A `to_world` that mirrors (negative determinant) would turn the winding
//! inside out; the winding is swapped on load so the front stays the front (as pbrt does).
//! The shading normal is the interpolated vertex normal (not forced to `ng`'s side), or `ng`
//! without vertex normals or with `face_normals`.
//!
//! UVs are interpolated from the vertex UVs; without them each triangle gets (0,0), (1,0),
//! (1,1) at its three corners. dp/du and dp/dv solve the triangle's UV parametrisation; for
//! degenerate UVs an arbitrary tangent frame around `ng` is used.
//!
//! Intersection: the watertight test of Woop, Benthin and Wald, "Watertight Ray/Triangle
//! Intersection", JCGT 2(1), 2013, with an f64 fallback on edges. Zero-area triangles are
//! dropped at construction ([`TriangleMesh::degenerate_dropped`] counts them).
//!
//! Direct sampling picks a triangle in proportion to its area (an alias table, O(1) per
//! sample; see [`super::alias`]) and a uniform point on it (Heitz 2019), so the density is
//! 1/area over the whole mesh. The table (8 bytes per triangle) is built on the first sample,
//! so meshes that never emit do not pay for it.
use super::alias::AliasTable;
use super::{area_to_solid_angle, Hit, ShapeSample, SurfaceInteraction};
use crate::math::{warp, Bounds3, Frame, Ray, Transform, Vec2, Vec3};
use std::sync::OnceLock;

/// Invalid mesh data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// An index refers past the end of the vertex arrays.
    #[error("triangle {triangle} refers to vertex {index}, but the mesh has {vertices} vertices")]
    IndexOutOfRange {
        triangle: usize,
        index: u32,
        vertices: usize,
    },
    /// An attribute array does not have one entry per vertex.
    #[error("{attribute} has {got} entries, expected one per vertex ({vertices})")]
    AttributeLength {
        attribute: &'static str,
        got: usize,
        vertices: usize,
    },
    /// A position is NaN or infinite (after the transform).
    #[error("vertex {0} has a non-finite position")]
    NonFinite(usize),
    /// No triangle with positive area remains.
    #[error(
        "the mesh has no triangles with non-zero area ({dropped} degenerate triangles dropped)"
    )]
    Empty { dropped: usize },
}

/// A triangle mesh in world space.
#[derive(Clone, Debug)]
pub struct TriangleMesh {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    indices: Vec<[u32; 3]>,
    flip_normals: bool,
    /// Triangles by area, for direct sampling; built on first use.
    alias: OnceLock<AliasTable>,
    area: f32,
    bounds: Bounds3,
    dropped: usize,
}

impl TriangleMesh {
    /// A mesh from object-space arrays; see the module header for the conventions.
    pub fn new(
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
        indices: Vec<[u32; 3]>,
        to_world: &Transform,
        flip_normals: bool,
        face_normals: bool,
    ) -> Result<TriangleMesh, MeshError> {
        let nv = positions.len();
        // An attribute, when given, has one value per vertex.
        let per_vertex = |attribute, got: Option<usize>| match got {
            Some(got) if got != nv => Err(MeshError::AttributeLength {
                attribute,
                got,
                vertices: nv,
            }),
            _ => Ok(()),
        };
        per_vertex("normals", normals.as_ref().map(Vec::len))?;
        per_vertex("uvs", uvs.as_ref().map(Vec::len))?;
        // Large meshes on all threads (each step is per triangle or per vertex, and the
        // results are the serial ones: the first bad index or value, bounds by min and max, the
        // area summed in triangle order); on one, the 1M-triangle mesh spent ~20 ms here.
        use rayon::prelude::*;
        const MIN: usize = 1 << 14;
        let bad = |tri: &[u32; 3]| tri.iter().find(|&&k| k as usize >= nv).copied();
        if let Some(i) = indices
            .par_iter()
            .with_min_len(MIN)
            .position_first(|t| bad(t).is_some())
        {
            return Err(MeshError::IndexOutOfRange {
                triangle: i,
                index: bad(&indices[i]).unwrap_or_default(),
                vertices: nv,
            });
        }
        let identity = to_world.is_identity();
        let mut positions = positions;
        if !identity {
            positions
                .par_iter_mut()
                .with_min_len(MIN)
                .for_each(|p| *p = to_world.point(*p));
        }
        if let Some(i) = positions
            .par_iter()
            .with_min_len(MIN)
            .position_first(|p| !p.is_finite())
        {
            return Err(MeshError::NonFinite(i));
        }
        let normals = if face_normals {
            None
        } else {
            normals.map(|mut ns| {
                ns.par_iter_mut().with_min_len(MIN).for_each(|n| {
                    let m = if identity { *n } else { to_world.normal(*n) };
                    *n = m.normalize_or_zero();
                });
                ns
            })
        };
        let swap = to_world.swaps_handedness();
        let given = indices.len();
        let mut indices = indices;
        // Each triangle's area (0 where it is dropped) and the bounds of those kept, in
        // parallel; then the kept ones are moved down in place (a second index array would add
        // 12 bytes per triangle to the peak; the areas add 4, for the time being) and their
        // areas summed in order.
        let (area, bounds) = indices
            .par_iter_mut()
            .with_min_len(MIN)
            .map(|tri| {
                if swap {
                    tri.swap(1, 2);
                }
                let [a, b, c] = tri.map(|k| positions[k as usize]);
                let area = 0.5 * (b - a).cross(c - a).length();
                let mut bounds = Bounds3::EMPTY;
                if !super::positive_finite(area) {
                    return (0.0, bounds);
                }
                bounds.grow(a);
                bounds.grow(b);
                bounds.grow(c);
                (area, bounds)
            })
            .fold(
                || (Vec::new(), Bounds3::EMPTY),
                |(mut v, b), (area, t)| {
                    v.push(area);
                    (v, b.union(&t))
                },
            )
            .map(|(v, b)| (vec![v], b))
            .reduce(
                || (Vec::new(), Bounds3::EMPTY),
                |(mut v, b), (w, c)| {
                    v.extend(w);
                    (v, b.union(&c))
                },
            );
        let mut total = 0.0f64;
        let mut kept = 0;
        for (i, &a) in area.iter().flatten().enumerate() {
            if a > 0.0 {
                indices[kept] = indices[i];
                kept += 1;
                total += a as f64;
            }
        }
        drop(area);
        indices.truncate(kept);
        indices.shrink_to_fit();
        let dropped = given - indices.len();
        if indices.is_empty() {
            return Err(MeshError::Empty { dropped });
        }
        Ok(TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
            flip_normals,
            alias: OnceLock::new(),
            area: total as f32,
            bounds,
            dropped,
        })
    }

    /// Whether normals are flipped (`flip_normals`).
    #[inline]
    pub(crate) fn flips_normals(&self) -> bool {
        self.flip_normals
    }

    /// The corner indices of triangle `prim`.
    #[inline]
    pub(crate) fn triangle(&self, prim: u32) -> [u32; 3] {
        self.indices[prim as usize]
    }

    /// Vertex position `k`.
    #[inline]
    pub(crate) fn position(&self, k: u32) -> Vec3 {
        self.positions[k as usize]
    }

    /// Requests the memory of triangle `prim`'s corner indices (for
    /// [`TriangleMesh::prefetch_attributes`] and [`TriangleMesh::corner_attributes`] soon
    /// after: on a large mesh each is a cache miss).
    #[inline]
    pub(crate) fn prefetch_triangle(&self, prim: u32) {
        if let Some(t) = self.indices.get(prim as usize) {
            crate::accel::simd::prefetch(t, 1);
        }
    }

    /// Requests the memory of the vertex normals and UVs that
    /// [`TriangleMesh::corner_attributes`] reads for triangle `prim`.
    #[inline]
    pub(crate) fn prefetch_attributes(&self, prim: u32) {
        let Some(tri) = self.indices.get(prim as usize) else {
            return;
        };
        for &k in tri {
            if let Some(n) = self.normals.as_ref().and_then(|n| n.get(k as usize)) {
                crate::accel::simd::prefetch(n, 1);
            }
            if let Some(uv) = self.uvs.as_ref().and_then(|uv| uv.get(k as usize)) {
                crate::accel::simd::prefetch(uv, 1);
            }
        }
    }

    /// The UVs of triangle `prim`'s corners (defaults without vertex UVs) and their vertex
    /// normals (if the mesh has them), as [`TriangleMesh::interaction_at`] uses them.
    #[inline]
    pub(crate) fn corner_attributes(&self, prim: u32) -> ([Vec2; 3], Option<[Vec3; 3]>) {
        let tri = self.indices[prim as usize];
        let uv = self.uv_corners(Some(tri));
        let n = self.normals.as_ref().map(|n| tri.map(|k| n[k as usize]));
        (uv, n)
    }

    /// Number of zero-area triangles dropped at construction.
    pub fn degenerate_dropped(&self) -> usize {
        self.dropped
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Whether shading uses interpolated vertex normals.
    pub fn has_vertex_normals(&self) -> bool {
        self.normals.is_some()
    }

    /// Whether the mesh carries vertex UVs.
    pub fn has_uvs(&self) -> bool {
        self.uvs.is_some()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// World-space corners of triangle `prim`.
    #[inline]
    pub fn vertices(&self, prim: u32) -> [Vec3; 3] {
        self.indices[prim as usize].map(|k| self.positions[k as usize])
    }

    /// World bounds of one triangle.
    pub fn triangle_bounds(&self, prim: u32) -> Bounds3 {
        let [a, b, c] = self.vertices(prim);
        Bounds3 {
            min: a.min(b).min(c),
            max: a.max(b).max(c),
        }
    }

    /// Watertight intersection; returns t in (0, ray.t_max) and the barycentrics (b1, b2).
    #[inline]
    pub fn intersect_triangle(&self, prim: u32, ray: &Ray) -> Option<(f32, Vec2)> {
        let [p0, p1, p2] = self.vertices(prim);
        intersect_watertight(p0, p1, p2, ray)
    }

    /// [`Self::intersect_triangle`] with the ray's shear precomputed.
    #[inline]
    pub fn intersect_triangle_sheared(
        &self,
        prim: u32,
        ray: &Ray,
        sr: &ShearedRay,
    ) -> Option<(f32, Vec2)> {
        let [p0, p1, p2] = self.vertices(prim);
        intersect_watertight_sheared(p0, p1, p2, ray, sr)
    }

    /// World bounds of the mesh.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// UVs of a triangle's corners (`tri` is its index triple, needed only with vertex UVs).
    fn uv_corners(&self, tri: Option<[u32; 3]>) -> [Vec2; 3] {
        match (&self.uvs, tri) {
            (Some(uv), Some(tri)) => tri.map(|k| uv[k as usize]),
            _ => [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::ONE],
        }
    }

    fn geometric_normal(&self, p: &[Vec3; 3]) -> Vec3 {
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        if self.flip_normals {
            -n
        } else {
            n
        }
    }

    /// Surface geometry at a hit; the point is recomputed from the barycentrics.
    pub fn interaction(&self, hit: &Hit, _ray: &Ray) -> SurfaceInteraction {
        self.interaction_at(hit, self.vertices(hit.prim))
    }

    /// [`Self::interaction`] with the hit triangle's corners `p` at hand (the BVH keeps
    /// copies); the index triple is read only for vertex normals or UVs.
    pub fn interaction_at(&self, hit: &Hit, p: [Vec3; 3]) -> SurfaceInteraction {
        let tri =
            (self.normals.is_some() || self.uvs.is_some()).then(|| self.indices[hit.prim as usize]);
        let (b1, b2) = (hit.uv.x, hit.uv.y);
        let b0 = 1.0 - b1 - b2;
        let pos = b0 * p[0] + b1 * p[1] + b2 * p[2];
        let ng = self.geometric_normal(&p);
        let uvc = self.uv_corners(tri);
        let uv = b0 * uvc[0] + b1 * uvc[1] + b2 * uvc[2];
        let (dpdu, dpdv) = tangents(&p, &uvc, ng);
        let ns = match (&self.normals, tri) {
            (Some(n), Some(tri)) => {
                let s = b0 * n[tri[0] as usize] + b1 * n[tri[1] as usize] + b2 * n[tri[2] as usize];
                let s = s.normalize_or_zero();
                match (s == Vec3::ZERO, self.flip_normals) {
                    (true, _) => ng,
                    (false, true) => -s,
                    (false, false) => s,
                }
            }
            _ => ng,
        };
        SurfaceInteraction {
            p: pos,
            t: hit.t,
            ng,
            ns,
            uv,
            dpdu,
            dpdv,
            shape: hit.shape,
            prim: hit.prim,
        }
    }

    /// Total world-space area.
    pub fn area(&self) -> f32 {
        self.area
    }

    /// Area of triangle `prim`, as the sampling table weighs it.
    fn triangle_area(&self, prim: usize) -> f64 {
        let [a, b, c] = self.vertices(prim as u32);
        0.5 * (b - a).cross(c - a).length() as f64
    }

    /// The alias table over the triangle areas (built on the first call).
    pub(crate) fn alias(&self) -> &AliasTable {
        self.alias.get_or_init(|| {
            let areas: Vec<f64> = (0..self.indices.len())
                .map(|i| self.triangle_area(i))
                .collect();
            // Construction keeps only triangles of positive finite area, and at least one.
            AliasTable::new(&areas).expect("a mesh has triangles of positive area")
        })
    }

    /// Samples a point uniformly by area; density converted to solid angle at `ref_p`.
    pub fn sample_direct(&self, ref_p: Vec3, u: Vec2) -> Option<ShapeSample> {
        // The fraction of u.x left after choosing the triangle positions the point in it.
        let (i, ux) = self.alias().sample(u.x);
        let b = warp::square_to_uniform_triangle(Vec2::new(ux, u.y));
        let (b0, b1) = (b.x, b.y);
        let b2 = 1.0 - b0 - b1;
        let tri = self.indices[i];
        let p = tri.map(|k| self.positions[k as usize]);
        let pos = b0 * p[0] + b1 * p[1] + b2 * p[2];
        let n = self.geometric_normal(&p);
        let uvc = self.uv_corners(Some(tri));
        let uv = b0 * uvc[0] + b1 * uvc[1] + b2 * uvc[2];
        let pdf = area_to_solid_angle(1.0 / self.area, ref_p, pos, n);
        if !super::positive_finite(pdf) {
            return None;
        }
        Some(ShapeSample { p: pos, n, uv, pdf })
    }

    /// Solid-angle density of [`TriangleMesh::sample_direct`] choosing `p` (normal `n`).
    pub fn pdf_direct(&self, ref_p: Vec3, p: Vec3, n: Vec3) -> f32 {
        area_to_solid_angle(1.0 / self.area, ref_p, p, n)
    }
}

/// dp/du and dp/dv of a triangle from its UV parametrisation; an arbitrary frame around `ng`
/// when the UVs are degenerate.
fn tangents(p: &[Vec3; 3], uv: &[Vec2; 3], ng: Vec3) -> (Vec3, Vec3) {
    let (d02, d12) = (uv[0] - uv[2], uv[1] - uv[2]);
    let (e02, e12) = (p[0] - p[2], p[1] - p[2]);
    let det = d02.x * d12.y - d02.y * d12.x;
    if det.abs() > 1e-12 {
        let inv = 1.0 / det;
        let dpdu = (d12.y * e02 - d02.y * e12) * inv;
        let dpdv = (d02.x * e12 - d12.x * e02) * inv;
        if dpdu.cross(dpdv).length_squared() > 0.0 && dpdu.is_finite() && dpdv.is_finite() {
            return (dpdu, dpdv);
        }
    }
    let f = Frame::from_z(ng);
    (f.s, f.t)
}

/// The watertight ray–triangle test; returns (t, (b1, b2)) for the barycentrics of p1 and p2.
#[inline]
pub fn intersect_watertight(p0: Vec3, p1: Vec3, p2: Vec3, ray: &Ray) -> Option<(f32, Vec2)> {
    intersect_watertight_sheared(p0, p1, p2, ray, &ShearedRay::new(ray.d)?)
}

/// The per-ray part of the watertight test (axis permutation and shear), computed once per ray
/// and shared by every triangle it meets.
#[derive(Clone, Copy, Debug)]
pub struct ShearedRay {
    /// The permuted axes: `kz` is the dominant direction component.
    pub(crate) kx: usize,
    pub(crate) ky: usize,
    pub(crate) kz: usize,
    /// The shear: d[kx]/d[kz], d[ky]/d[kz] and 1/d[kz].
    pub(crate) sx: f32,
    pub(crate) sy: f32,
    pub(crate) sz: f32,
}

impl ShearedRay {
    /// The shear for direction `d`; `None` for a zero direction.
    #[inline]
    pub fn new(d: Vec3) -> Option<ShearedRay> {
        // Permute axes so that the dominant direction component is z (keeping handedness).
        // Branch-free (a table and array indexing): for incoherent rays the dominant axis is
        // unpredictable, and `Vec3`'s index is a `match`.
        let ad = d.abs();
        let a = d.to_array();
        // kz by (x > y, x > z, y > z): x if it beats both, else y if it beats z, else z.
        const KZ: [usize; 8] = [2, 2, 2, 0, 1, 2, 1, 0];
        let key =
            (ad.x > ad.y) as usize | ((ad.x > ad.z) as usize) << 1 | ((ad.y > ad.z) as usize) << 2;
        let kz = KZ[key];
        let kx0 = (kz + 1) % 3;
        let ky0 = (kx0 + 1) % 3;
        let (kx, ky) = if a[kz] < 0.0 { (ky0, kx0) } else { (kx0, ky0) };
        let dz = a[kz];
        if dz == 0.0 {
            return None;
        }
        Some(ShearedRay {
            kx,
            ky,
            kz,
            sx: a[kx] / dz,
            sy: a[ky] / dz,
            sz: 1.0 / dz,
        })
    }
}

/// [`intersect_watertight`] with the ray's shear precomputed.
#[inline]
pub fn intersect_watertight_sheared(
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    ray: &Ray,
    sr: &ShearedRay,
) -> Option<(f32, Vec2)> {
    let ShearedRay {
        kx,
        ky,
        kz,
        sx,
        sy,
        sz,
    } = *sr;
    let a = p0 - ray.o;
    let b = p1 - ray.o;
    let c = p2 - ray.o;
    // Shear the vertices into the ray's space: the ray becomes the +z axis through the origin.
    let (ax, ay) = (a[kx] - sx * a[kz], a[ky] - sy * a[kz]);
    let (bx, by) = (b[kx] - sx * b[kz], b[ky] - sy * b[kz]);
    let (cx, cy) = (c[kx] - sx * c[kz], c[ky] - sy * c[kz]);
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        // On an edge f32 rounding decides the sign; redo the edge functions exactly enough.
        u = edge_f64(cx, by, cy, bx);
        v = edge_f64(ax, cy, ay, cx);
        w = edge_f64(bx, ay, by, ax);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let (az, bz, cz) = (sz * a[kz], sz * b[kz], sz * c[kz]);
    let t_scaled = u * az + v * bz + w * cz;
    // Compare t·det against the interval (0, t_max·det) without dividing.
    if det < 0.0 {
        if t_scaled >= 0.0 || t_scaled <= ray.t_max * det {
            return None;
        }
    } else if t_scaled <= 0.0 || t_scaled >= ray.t_max * det {
        return None;
    }
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    if !(t > 0.0 && t < ray.t_max) {
        return None;
    }
    // Reject hits closer than the rounding error of t itself (the forward error bound of the
    // watertight test, Woop et al. 2013 with the analysis of Pharr, Jakob & Humphreys,
    // "Physically Based Rendering" 3rd ed., §3.9.6). Without it, a ray leaving a large flat
    // triangle at a grazing angle could re-hit its neighbour at t ≈ 1e-3: a false shadow edge
    // along the diagonal of a kilometre-wide ground rectangle.
    let max_zt = az.abs().max(bz.abs()).max(cz.abs());
    let max_xt = ax.abs().max(bx.abs()).max(cx.abs());
    let max_yt = ay.abs().max(by.abs()).max(cy.abs());
    let delta_z = gamma(3) * max_zt;
    let delta_x = gamma(5) * (max_xt + max_zt);
    let delta_y = gamma(5) * (max_yt + max_zt);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = u.abs().max(v.abs()).max(w.abs());
    let delta_t =
        3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv.abs();
    if t <= delta_t {
        return None;
    }
    Some((t, Vec2::new(v * inv, w * inv)))
}

/// The edge function x·y − z·q in f64 (exact products), rounded once: the watertight test's
/// fallback when the f32 value is zero.
#[inline]
pub(crate) fn edge_f64(x: f32, y: f32, z: f32, q: f32) -> f32 {
    (x as f64 * y as f64 - z as f64 * q as f64) as f32
}

/// Bound on the relative rounding error of n chained f32 operations: nε/(1 − nε).
#[inline]
pub(crate) fn gamma(n: i32) -> f32 {
    let e = f32::EPSILON * 0.5 * n as f32;
    e / (1.0 - e)
}

#[cfg(test)]
#[path = "mesh_tests.rs"]
mod tests;
