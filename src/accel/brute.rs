//! Brute-force intersection: tests every primitive of every shape. For tests only.
use super::Accel;
use crate::math::Ray;
use crate::shape::{Hit, Shape};

/// The oracle accelerator: no structure at all.
#[derive(Clone, Copy, Debug, Default)]
pub struct BruteForce;

impl Accel for BruteForce {
    fn intersect(&self, shapes: &[Shape], ray: &Ray) -> Option<Hit> {
        let mut r = *ray;
        let mut best = None;
        for (s, shape) in shapes.iter().enumerate() {
            for p in 0..shape.prim_count() as u32 {
                if let Some((t, uv)) = shape.intersect_prim(p, &r) {
                    r.t_max = t;
                    best = Some(Hit {
                        t,
                        shape: s as u32,
                        prim: p,
                        uv,
                    });
                }
            }
        }
        best
    }

    fn occluded(&self, shapes: &[Shape], ray: &Ray) -> bool {
        shapes.iter().any(|shape| {
            (0..shape.prim_count() as u32).any(|p| shape.intersect_prim(p, ray).is_some())
        })
    }
}
