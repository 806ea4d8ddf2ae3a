//! The surface at each lane's hit: position, geometric and shading normals and ∂p/∂u, as
//! [`crate::shape::mesh::TriangleMesh::interaction_at`] computes them for triangles (in lanes,
//! from the corners kept in the BVH's leaf blocks) and as each shape's own code computes them
//! for the others (lane by lane).

use super::lookup::Groups;
use super::pool::Pool;
use super::vertex::{lanes, load_v3, Ctx};
use crate::accel::{RawHit, BLOCK_WORDS};
use crate::math::frame::FrameL;
use crate::shape::Shape;
use crate::simd::{Float, Int, Mask, V3};

/// Triangles from which a mesh's arrays outgrow the caches (its indices alone 768 KB).
pub(super) const BIG_MESH: usize = 1 << 16;

/// Requests, for every hit on a mesh of [`BIG_MESH`] triangles or more among `hits`, the
/// memory [`surfaces`] reads from the mesh's own arrays: the corner indices (`corners` false,
/// right after tracing), or through them the corners' normals and UVs (`corners` true, once the
/// indices have arrived: just before shading). Each is a cache miss on such a mesh, which
/// shading took one lane at a time; requested for the whole pool at once, the loads overlap.
/// (On small meshes the pass costs more than it saves.)
pub(super) fn prefetch_meshes(shapes: &[Shape], hits: &[Option<RawHit>], corners: bool) {
    for h in hits.iter().flatten() {
        if let Some(Shape::Mesh(m)) = shapes.get(h.hit.shape as usize) {
            if m.triangle_count() < BIG_MESH {
                continue;
            }
            if corners {
                m.prefetch_attributes(h.hit.prim);
            } else {
                m.prefetch_triangle(h.hit.prim);
            }
        }
    }
}

/// The geometry the vertex needs.
pub(super) struct Surface<F> {
    pub p: V3<F>,
    pub ng: V3<F>,
    pub ns: V3<F>,
    pub dpdu: V3<F>,
}

/// The surfaces of the lanes of `m`, whose shapes are `shape`.
#[inline(always)]
pub(super) fn surfaces<F: Float>(
    c: &Ctx,
    pool: &Pool,
    base: usize,
    m: F::M,
    shapes: &Groups<F>,
    w: &mut [[f32; 16]; 16],
) -> Surface<F> {
    let scene = c.scene;
    let mesh = m & shapes.i(&c.prog.shape_mesh).eq(F::I::splat(1));
    // Lane by lane: what lives in each shape's own arrays (a triangle's corner UVs and
    // normals), or the whole interaction of other shapes.
    let mut flip = 0u32;
    let mut has_normals = 0u32;
    for i in lanes(m.bits()) {
        let h = pool.hit[base + i].expect("a lane hit");
        match &scene.shapes[h.hit.shape as usize] {
            Shape::Mesh(mesh) => {
                flip |= (mesh.flips_normals() as u32) << i;
                let (uv, normals) = mesh.corner_attributes(h.hit.prim);
                for (k, q) in uv.iter().enumerate() {
                    w[2 * k][i] = q.x;
                    w[2 * k + 1][i] = q.y;
                }
                if let Some(n) = normals {
                    has_normals |= 1 << i;
                    for (k, q) in n.iter().enumerate() {
                        for a in 0..3 {
                            w[6 + 3 * k + a][i] = q[a];
                        }
                    }
                }
            }
            Shape::Sphere(sphere) => {
                // No texture coordinates are needed: skip their arc tangents.
                let (p, ng, dpdu) = sphere.shading_geometry(&h.hit, &pool.ray(base + i));
                for a in 0..3 {
                    w[a][i] = p[a];
                    w[3 + a][i] = ng[a];
                    w[6 + a][i] = ng[a];
                    w[9 + a][i] = dpdu[a];
                }
            }
            _ => {
                let si = scene
                    .bvh
                    .raw_interaction(&scene.shapes, &h, &pool.ray(base + i));
                for a in 0..3 {
                    w[a][i] = si.p[a];
                    w[3 + a][i] = si.ng[a];
                    w[6 + a][i] = si.ns[a];
                    w[9 + a][i] = si.dpdu[a];
                }
            }
        }
    }
    let other = Surface {
        p: load_v3(w, 0),
        ng: load_v3(w, 3),
        ns: load_v3(w, 6),
        dpdu: load_v3(w, 9),
    };
    if !mesh.any() {
        return other;
    }

    // Triangles, from the corners in the leaf block and the barycentrics of the hit.
    let words = scene.bvh.block_words();
    let slot = F::I::load_at(&pool.h_block[..], base).mul_lo(F::I::splat(BLOCK_WORDS as i32))
        + F::I::load_at(&pool.h_lane[..], base);
    let slot = F::I::select(mesh, slot, F::I::splat(0));
    let (p0, p1, p2) = (
        corner(words, slot, 0),
        corner(words, slot, 1),
        corner(words, slot, 2),
    );
    let b1 = F::load_at(&pool.h_u[..], base);
    let b2 = F::load_at(&pool.h_v[..], base);
    let b0 = F::splat(1.0) - b1 - b2;
    let p = p0 * b0 + p1 * b1 + p2 * b2;
    let flip = F::M::from_bits(flip);
    let n = (p1 - p0).cross(p2 - p0).normalize();
    let ng = V3::select(flip, -n, n);
    // dp/du and dp/dv from the corners' UVs; a frame around ng where they are degenerate.
    let (u0, v0) = (F::load(&w[0]), F::load(&w[1]));
    let (u1, v1) = (F::load(&w[2]), F::load(&w[3]));
    let (u2, v2) = (F::load(&w[4]), F::load(&w[5]));
    let (d02x, d02y, d12x, d12y) = (u0 - u2, v0 - v2, u1 - u2, v1 - v2);
    let (e02, e12) = (p0 - p2, p1 - p2);
    let det = d02x * d12y - d02y * d12x;
    let inv = F::splat(1.0) / det;
    let dpdu = (e02 * d12y - e12 * d02y) * inv;
    let dpdv = (e12 * d02x - e02 * d12x) * inv;
    let ok = det.abs().gt(F::splat(1e-12))
        & dpdu.cross(dpdv).length_squared().gt(F::splat(0.0))
        & dpdu.is_finite()
        & dpdv.is_finite();
    let dpdu = V3::select(ok, dpdu, FrameL::from_z(ng).s);
    // The interpolated vertex normal (on ng's side only through flip_normals), or ng.
    let with_n = F::M::from_bits(has_normals);
    let ns = if with_n.any() {
        let s = load_v3(w, 6) * b0 + load_v3(w, 9) * b1 + load_v3(w, 12) * b2;
        let s = s.normalize_or_zero();
        let s = V3::select(flip, -s, s);
        V3::select(with_n.and_not(s.is_zero()), s, ng)
    } else {
        ng
    };
    Surface {
        p: V3::select(mesh, p, other.p),
        ng: V3::select(mesh, ng, other.ng),
        ns: V3::select(mesh, ns, other.ns),
        dpdu: V3::select(mesh, dpdu, other.dpdu),
    }
}

/// Corner `k` of the triangles in the leaf-block slots `slot` (word offsets).
#[inline(always)]
fn corner<F: Float>(words: &[f32], slot: F::I, k: i32) -> V3<F> {
    V3::new(
        F::gather(words, slot + F::I::splat(12 * k)),
        F::gather(words, slot + F::I::splat(12 * k + 4)),
        F::gather(words, slot + F::I::splat(12 * k + 8)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Transform, Vec2, Vec3};
    use crate::shape::{Hit, TriangleMesh};

    #[test]
    fn prefetching_reads_only_what_exists() {
        // A big mesh (strips of triangles) with normals and UVs, a small one, a sphere, and
        // hits on each, including primitives and shapes that do not exist: the passes request
        // what is there and never index out of bounds.
        let n = BIG_MESH + 2;
        let positions: Vec<Vec3> = (0..n + 2)
            .map(|i| Vec3::new(i as f32, (i % 2) as f32, 0.0))
            .collect();
        let indices: Vec<[u32; 3]> = (0..n as u32).map(|i| [i, i + 1, i + 2]).collect();
        let normals = Some(vec![Vec3::Z; n + 2]);
        let uvs = Some(vec![Vec2::ZERO; n + 2]);
        let mesh = |idx: Vec<[u32; 3]>| {
            let big = idx.len() >= BIG_MESH;
            TriangleMesh::new(
                positions.clone(),
                normals.clone(),
                if big { uvs.clone() } else { None },
                idx,
                &Transform::IDENTITY,
                false,
                false,
            )
            .unwrap()
        };
        let shapes = [
            Shape::Mesh(mesh(indices.clone())),
            Shape::Mesh(mesh(indices[..8].to_vec())),
            Shape::Sphere(crate::shape::sphere::Sphere::simple(Vec3::ZERO, 1.0)),
        ];
        let hit = |shape, prim| {
            Some(RawHit {
                hit: Hit {
                    t: 1.0,
                    shape,
                    prim,
                    uv: Vec2::ZERO,
                },
                block: 0,
                lane: 0,
            })
        };
        let hits = [
            hit(0, 0),
            hit(0, n as u32 - 1),
            hit(0, n as u32),
            hit(0, u32::MAX),
            hit(1, 3),
            hit(1, 100),
            hit(2, 0),
            hit(7, 0),
            None,
        ];
        prefetch_meshes(&shapes, &hits, false);
        prefetch_meshes(&shapes, &hits, true);
    }
}
