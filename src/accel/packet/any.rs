//! Occlusion in packets: the walk of the tree with a stack of (subtree, rays), rays leaving
//! the packet as soon as something blocks them.
use super::alone;
use super::lanes::{decide, Lanes, RayColumns};
use super::walkers::{self, Defer, Queue};
use crate::accel::block::{ANALYTIC, EMPTY};
use crate::accel::simd::Vec8;
use crate::accel::traverse::{self, View, STACK};
use crate::accel::wide::{leaf_range, EMPTY_CHILD, LEAF};
use crate::math::Ray;
use crate::shape::Shape;
use crate::simd::{lanes, Float};
use std::mem::MaybeUninit;

/// [`any`] for the rays `base .. base + out.len()` of `rays`.
#[inline(always)]
pub fn any_columns<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &RayColumns,
    base: usize,
    out: &mut [bool],
) {
    occlusion::<F, V>(v, shapes, &Lanes::from_columns(rays, base, out.len()), out);
}

/// Occlusion of `rays` (at most `F::LANES`): `out[i]` for `rays[i]`, the same as
/// [`traverse::any`] gives ray by ray.
#[inline(always)]
pub fn any<F: Float, V: Vec8>(v: View, shapes: &[Shape], rays: &[Ray], out: &mut [bool]) {
    occlusion::<F, V>(v, shapes, &Lanes::new(rays), out);
}

/// Occlusion of the packet `p` into `out`.
#[inline(always)]
fn occlusion<F: Float, V: Vec8>(v: View, shapes: &[Shape], p: &Lanes<F>, out: &mut [bool]) {
    let mut blocked = 0u32;
    if v.root != EMPTY_CHILD && p.valid != 0 {
        blocked = any_walk::<F, V>(v, shapes, p, None);
    }
    for (i, o) in out.iter_mut().enumerate() {
        *o = blocked & (1 << i) != 0;
    }
}

/// [`any_columns`] for a whole batch: as [`super::closest_raw_batch`], the packets' walks
/// first and then their queued walks, chunk by chunk, on a tree that [`View::interleave`]s.
#[inline(always)]
pub fn any_batch<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &RayColumns,
    out: &mut [bool],
) {
    if !v.interleave || v.root == EMPTY_CHILD {
        for (k, o) in out.chunks_mut(F::LANES).enumerate() {
            any_columns::<F, V>(v, shapes, rays, F::LANES * k, o);
        }
        return;
    }
    let mut queue = Queue::take();
    let mut packets: Vec<(u32, u32)> = Vec::with_capacity(walkers::CHUNK / F::LANES);
    for (k, chunk) in out.chunks_mut(walkers::CHUNK).enumerate() {
        packets.clear();
        for (j, o) in chunk.chunks(F::LANES).enumerate() {
            let p = Lanes::<F>::from_columns(rays, k * walkers::CHUNK + F::LANES * j, o.len());
            let mut d = queue.defer(F::LANES * j);
            let blocked = match p.valid {
                0 => 0,
                _ => any_walk::<F, V>(v, shapes, &p, Some(&mut d)),
            };
            let used = d.used;
            for i in lanes(used) {
                let (sr, inv) = p.single(i);
                let s = &mut queue.subjects[F::LANES * j + i];
                (s.ray, s.sr, s.inv) = (p.ray(i), sr, inv);
                // A ray its packet found blocked needs none of its walks.
                s.blocked = blocked & (1 << i) != 0;
            }
            packets.push((blocked, used));
        }
        queue.run::<V, u32>(v, shapes, chunk.len());
        for (j, (o, &(blocked, used))) in chunk.chunks_mut(F::LANES).zip(&packets).enumerate() {
            for (i, o) in o.iter_mut().enumerate() {
                *o = blocked & (1 << i) != 0
                    || (used & (1 << i) != 0 && queue.subjects[F::LANES * j + i].blocked);
            }
        }
    }
    queue.give_back();
}

/// The packet's walk; the rays that go on alone do so at once, or are queued in `defer`.
/// Returns the rays found blocked.
#[inline(always)]
fn any_walk<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    p: &Lanes<F>,
    mut defer: Option<&mut Defer>,
) -> u32 {
    let mut stack = [const { MaybeUninit::<(u32, u32)>::uninit() }; STACK];
    let mut sp = 0usize;
    let mut blocked = 0u32;
    let (mut cur, mut active) = (v.root, p.valid);
    let inf = F::splat(f32::INFINITY);
    loop {
        if alone(cur, active, F::LANES, defer.is_some()) {
            if let Some(d) = defer.as_mut() {
                d.push(cur, active, F::splat(0.0));
            } else {
                let mut bits = active;
                while bits != 0 {
                    let i = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let (sr, inv) = p.single(i);
                    if traverse::any_from::<V>(v, shapes, &p.ray(i), &sr, inv, cur) {
                        blocked |= 1 << i;
                    }
                }
            }
        } else if cur & LEAF != 0 {
            let (first, n) = leaf_range(cur);
            'blocks: for b in &v.blocks[first..first + n] {
                for (slot, &id) in b.ids().iter().enumerate() {
                    if id == EMPTY {
                        continue;
                    }
                    let hit = if id & ANALYTIC != 0 {
                        any_analytic(&shapes[(id & !ANALYTIC) as usize], p, active)
                    } else {
                        p.triangle(b, slot, active, inf).0
                    };
                    blocked |= hit;
                    active &= !hit;
                    if active == 0 {
                        break 'blocks;
                    }
                }
            }
        } else {
            let node = &v.nodes[cur as usize];
            let mut next = None;
            for lane in 0..8 {
                let child = node.child[lane];
                if child == EMPTY_CHILD {
                    continue;
                }
                let (lo, hi) = node.corners(lane);
                let (_, rays) = p.enter(lo, hi, p.t_max, active);
                if rays == 0 {
                    continue;
                }
                match next {
                    None => next = Some((child, rays)),
                    Some(_) => {
                        stack[sp].write((child, rays));
                        sp += 1;
                    }
                }
            }
            if let Some((child, rays)) = next {
                (cur, active) = (child, rays);
                continue;
            }
        }
        loop {
            if sp == 0 || blocked == p.valid {
                return blocked;
            }
            sp -= 1;
            // SAFETY: slots below the old `sp` were all written by a push.
            let (node, rays) = unsafe { stack[sp].assume_init() };
            let keep = rays & !blocked;
            if keep != 0 {
                (cur, active) = (node, keep);
                break;
            }
        }
    }
}

/// The lanes of `active` whose ray hits the analytic primitive `shape`, ray by ray.
#[inline(always)]
fn any_analytic<F: Float>(shape: &Shape, p: &Lanes<F>, active: u32) -> u32 {
    let mut hit = 0;
    let mut bits = p.candidates(shape, active);
    while bits != 0 {
        let i = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        if decide(shape, &p.ray(i)).is_some() {
            hit |= 1 << i;
        }
    }
    hit
}
