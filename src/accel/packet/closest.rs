//! Closest hits in packets: the walk of the tree with a stack of (subtree, rays, entry
//! distances), and each lane's closest hit kept in lanes until the packet is done.
use super::lanes::{decide, Lanes, RayColumns};
use super::walkers::{self, Defer, Queue, Subject};
use super::{alone, MAX_LANES};
use crate::accel::block::{widen, Best, ANALYTIC, EMPTY, NO_HIT};
use crate::accel::bvh::SHORT_TABLE;
use crate::accel::simd::Vec8;
use crate::accel::traverse::{self, Found, View, STACK};
use crate::accel::wide::{leaf_range, EMPTY_CHILD, LEAF};
use crate::accel::RawHit;
use crate::math::{Ray, Vec2};
use crate::shape::{Hit, Shape};
use crate::simd::{lanes, Float, Int, Mask};
use std::mem::MaybeUninit;

/// The closest hits of the packet so far, in lanes: [`NO_HIT`] (flipped) where none.
struct Closest<F: Float> {
    t: F,
    /// Lane ids with the top bit flipped, so that a signed compare orders them as unsigned.
    id: F::I,
    /// Hit coordinates.
    u: F,
    v: F,
    /// Where the primitive's slot is: block index and lane.
    block: F::I,
    slot: F::I,
}

/// Flips the top bit: signed order of the result is unsigned order of `id`.
#[inline(always)]
fn ordered(id: u32) -> i32 {
    (id ^ (1 << 31)) as i32
}

impl<F: Float> Closest<F> {
    /// Nothing hit yet within the rays' own extents.
    #[inline(always)]
    fn new(p: &Lanes<F>) -> Closest<F> {
        Closest {
            t: p.t_max,
            id: F::I::splat(ordered(NO_HIT)),
            u: F::splat(0.0),
            v: F::splat(0.0),
            block: F::I::splat(0),
            slot: F::I::splat(0),
        }
    }

    /// Lane `i`'s closest hit so far as a [`Best`].
    #[inline(always)]
    fn best(&self, i: usize) -> Best {
        Best {
            t: self.t.lane(i),
            id: (self.id.lane(i) as u32) ^ (1 << 31),
        }
    }

    /// Records `f`, a closer hit for lane `i`.
    #[inline(always)]
    fn set(&mut self, i: usize, f: Found) {
        let m = F::M::from_bits(1 << i);
        self.t = F::select(m, F::splat(f.t), self.t);
        self.id = F::I::select(m, F::I::splat(ordered(f.id)), self.id);
        self.u = F::select(m, F::splat(f.uv.x), self.u);
        self.v = F::select(m, F::splat(f.uv.y), self.v);
        self.block = F::I::select(m, F::I::splat(f.block as i32), self.block);
        self.slot = F::I::select(m, F::I::splat(f.lane as i32), self.slot);
    }

    /// The hits found, lane by lane, into `out`, each with its shape and triangle named from
    /// `first` ([`super::bvh::hit`], in lanes where the table is short).
    #[inline(always)]
    fn write_raw(&self, first: &[u32], out: &mut [Option<RawHit>]) {
        let starts = &first[1..first.len() - 1];
        if starts.len() > SHORT_TABLE {
            let mut found = [None; MAX_LANES];
            self.write(&mut found[..out.len()]);
            for (o, f) in out.iter_mut().zip(found) {
                *o = f.map(|f| RawHit {
                    hit: crate::accel::bvh::hit(first, f),
                    block: f.block,
                    lane: f.lane,
                });
            }
            return;
        }
        // Triangles: the shape is the number of later shapes' first ids not beyond the id,
        // and the triangle the id less the last such first id (`first[0]` is 0).
        let id = self.id ^ F::I::splat(i32::MIN);
        let mut shape = F::I::splat(0);
        let mut base = F::I::splat(0);
        for &x in starts {
            // Triangle ids are below 2³¹, so a signed compare orders them.
            let m = !id.lt(F::I::splat(x as i32));
            shape = shape + F::I::select(m, F::I::splat(1), F::I::splat(0));
            base = F::I::select(m, F::I::splat(x as i32), base);
        }
        let triangle = !id.lt(F::I::splat(0));
        let shape = F::I::select(triangle, shape, id & F::I::splat(!(ANALYTIC as i32)));
        let prim = F::I::select(triangle, id - base, F::I::splat(0));
        let mut a = [[0u32; MAX_LANES]; 8];
        self.t.to_bits().store(&mut a[0][..]);
        id.store(&mut a[1][..]);
        self.u.to_bits().store(&mut a[2][..]);
        self.v.to_bits().store(&mut a[3][..]);
        self.block.store(&mut a[4][..]);
        self.slot.store(&mut a[5][..]);
        shape.store(&mut a[6][..]);
        prim.store(&mut a[7][..]);
        for (i, o) in out.iter_mut().enumerate() {
            *o = (a[1][i] != NO_HIT).then(|| RawHit {
                hit: Hit {
                    t: f32::from_bits(a[0][i]),
                    shape: a[6][i],
                    prim: a[7][i],
                    uv: Vec2::new(f32::from_bits(a[2][i]), f32::from_bits(a[3][i])),
                },
                block: a[4][i],
                lane: a[5][i],
            });
        }
    }

    /// The hits found, lane by lane, into `out`.
    #[inline(always)]
    fn write(&self, out: &mut [Option<Found>]) {
        let mut a = [[0u32; MAX_LANES]; 6];
        self.t.to_bits().store(&mut a[0][..]);
        self.id.store(&mut a[1][..]);
        self.u.to_bits().store(&mut a[2][..]);
        self.v.to_bits().store(&mut a[3][..]);
        self.block.store(&mut a[4][..]);
        self.slot.store(&mut a[5][..]);
        for (i, o) in out.iter_mut().enumerate() {
            let id = a[1][i] ^ (1 << 31);
            *o = (id != NO_HIT).then(|| Found {
                id,
                t: f32::from_bits(a[0][i]),
                uv: Vec2::new(f32::from_bits(a[2][i]), f32::from_bits(a[3][i])),
                block: a[4][i],
                lane: a[5][i],
            });
        }
    }

    /// Leaf `leaf` for the lanes of `active`.
    #[inline(always)]
    fn leaf(&mut self, v: View, shapes: &[Shape], p: &Lanes<F>, leaf: u32, active: u32) {
        let (first, n) = leaf_range(leaf);
        for (k, b) in v.blocks[first..first + n].iter().enumerate() {
            for (slot, &id) in b.ids().iter().enumerate() {
                if id == EMPTY {
                    continue;
                }
                let block = (first + k) as u32;
                if id & ANALYTIC != 0 {
                    self.analytic(shapes, p, id, block, slot, active);
                    continue;
                }
                let (hit, t, b1, b2) = p.triangle(b, slot, active, self.t);
                if hit == 0 {
                    continue;
                }
                // As `Best::takes`: closer, or as close with a lower id.
                let idl = F::I::splat(ordered(id));
                let take = hit & (t.lt(self.t) | (t.eq(self.t) & idl.lt(self.id))).bits();
                if take == 0 {
                    continue;
                }
                let m = F::M::from_bits(take);
                self.t = F::select(m, t, self.t);
                self.id = F::I::select(m, idl, self.id);
                self.u = F::select(m, b1, self.u);
                self.v = F::select(m, b2, self.v);
                self.block = F::I::select(m, F::I::splat(block as i32), self.block);
                self.slot = F::I::select(m, F::I::splat(slot as i32), self.slot);
            }
        }
    }

    /// An analytic primitive, ray by ray (its own exact test).
    #[inline(always)]
    fn analytic(
        &mut self,
        shapes: &[Shape],
        p: &Lanes<F>,
        id: u32,
        block: u32,
        slot: usize,
        active: u32,
    ) {
        let shape = &shapes[(id & !ANALYTIC) as usize];
        let mut bits = p.candidates(shape, active);
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            if let Some((t, uv)) = decide(shape, &p.ray(i)) {
                let mut best = self.best(i);
                if best.takes(t, id) {
                    self.set(
                        i,
                        Found {
                            id,
                            t,
                            uv,
                            block,
                            lane: slot as u32,
                        },
                    );
                }
            }
        }
    }

    /// Each ray of `active` alone through the subtree `node`.
    #[inline(always)]
    fn single<V: Vec8>(&mut self, v: View, shapes: &[Shape], p: &Lanes<F>, node: u32, active: u32) {
        let mut bits = active;
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let mut best = self.best(i);
            let (sr, inv) = p.single(i);
            if let Some(f) =
                traverse::closest_from::<V>(v, shapes, &p.ray(i), &sr, inv, node, &mut best)
            {
                self.set(i, f);
            }
        }
    }
}

/// A pending subtree: its reference, the rays that entered it and their entry distances.
#[derive(Clone, Copy)]
struct Entry<F> {
    node: u32,
    rays: u32,
    near: F,
}

/// [`closest`] with each hit's shape and triangle named, as [`super::Bvh::intersect_raw_n`]
/// gives them.
#[inline(always)]
pub fn closest_raw<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &[Ray],
    out: &mut [Option<RawHit>],
) {
    search::<F, V>(v, shapes, &Lanes::new(rays)).write_raw(v.first, out);
}

/// [`closest_raw`] for the rays `base .. base + out.len()` of `rays`.
#[inline(always)]
pub fn closest_raw_columns<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &RayColumns,
    base: usize,
    out: &mut [Option<RawHit>],
) {
    let p = Lanes::from_columns(rays, base, out.len());
    search::<F, V>(v, shapes, &p).write_raw(v.first, out);
}

/// The closest hits of `rays` in lanes.
#[inline(always)]
fn search<F: Float, V: Vec8>(v: View, shapes: &[Shape], p: &Lanes<F>) -> Closest<F> {
    let mut c = Closest::new(p);
    if v.root != EMPTY_CHILD && p.valid != 0 {
        walk::<F, V>(v, shapes, p, &mut c, None);
    }
    c
}

/// The closest hits of `rays` (at most `F::LANES`): `out[i]` for `rays[i]`, the same as
/// [`traverse::closest`] gives ray by ray.
#[inline(always)]
pub fn closest<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &[Ray],
    out: &mut [Option<Found>],
) {
    search::<F, V>(v, shapes, &Lanes::new(rays)).write(out);
}

/// The packet's walk; the rays that go on alone do so at once, or are queued in `defer`.
#[inline(always)]
fn walk<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    p: &Lanes<F>,
    c: &mut Closest<F>,
    mut defer: Option<&mut Defer>,
) {
    let mut stack = [const { MaybeUninit::<Entry<F>>::uninit() }; STACK];
    let mut sp = 0usize;
    // The current subtree, its rays and their entry distances.
    let (mut cur, mut active, mut entry) = (v.root, p.valid, F::splat(0.0));
    loop {
        if alone(cur, active, F::LANES, defer.is_some()) {
            match defer.as_mut() {
                Some(d) => d.push(cur, active, entry),
                None => c.single::<V>(v, shapes, p, cur, active),
            }
        } else if cur & LEAF != 0 {
            c.leaf(v, shapes, p, cur, active);
        } else {
            let node = &v.nodes[cur as usize];
            // The children entered, sorted far first by the entry of their first ray (keys
            // of entry bits and child lane; the entries' lanes stay where they were stored).
            let mut near = [[0.0f32; MAX_LANES]; 8];
            let mut rays = [0u32; 8];
            let mut keys = [0u64; 8];
            let mut n = 0;
            for lane in 0..8 {
                if node.child[lane] == EMPTY_CHILD {
                    continue;
                }
                let (lo, hi) = node.corners(lane);
                let (t, m) = p.enter(lo, hi, c.t, active);
                if m == 0 {
                    continue;
                }
                t.store(&mut near[lane][..]);
                rays[lane] = m;
                let key = ((near[lane][m.trailing_zeros() as usize].to_bits() as u64) << 32)
                    | lane as u64;
                traverse::insert_far_first(&mut keys, n, key);
                n += 1;
            }
            if n > 0 {
                for &key in &keys[..n - 1] {
                    let lane = (key & 7) as usize;
                    stack[sp].write(Entry {
                        node: node.child[lane],
                        rays: rays[lane],
                        near: F::load(&near[lane]),
                    });
                    sp += 1;
                }
                let lane = (keys[n - 1] & 7) as usize;
                (cur, active, entry) = (node.child[lane], rays[lane], F::load(&near[lane]));
                continue;
            }
        }
        loop {
            if sp == 0 {
                return;
            }
            sp -= 1;
            // SAFETY: slots below the old `sp` were all written by a push.
            let e = unsafe { stack[sp].assume_init() };
            // Widened as in `traverse`: an entry rounding just past an equally close hit may
            // still hold a tie.
            let keep = e.near.le(c.t * F::splat(widen(1.0))).bits() & e.rays;
            if keep != 0 {
                (cur, active, entry) = (e.node, keep, e.near);
                break;
            }
        }
    }
}

/// [`closest_raw_columns`] for a whole batch. On a tree that [`View::interleave`]s, the
/// batch goes in chunks of [`walkers::CHUNK`] rays: every packet's walk runs first, queueing
/// the single-ray walks of its rays that go on alone; then the chunk's queued walks run,
/// [`walkers::WALKERS`] at a time (`walkers.rs`), and each packet's hits are written with
/// theirs.
#[inline(always)]
pub fn closest_raw_batch<F: Float, V: Vec8>(
    v: View,
    shapes: &[Shape],
    rays: &RayColumns,
    out: &mut [Option<RawHit>],
) {
    if !v.interleave || v.root == EMPTY_CHILD {
        for (k, o) in out.chunks_mut(F::LANES).enumerate() {
            closest_raw_columns::<F, V>(v, shapes, rays, F::LANES * k, o);
        }
        return;
    }
    let mut queue = Queue::take();
    let mut packets: Vec<(Closest<F>, u32)> = Vec::with_capacity(walkers::CHUNK / F::LANES);
    for (k, chunk) in out.chunks_mut(walkers::CHUNK).enumerate() {
        packets.clear();
        for (j, o) in chunk.chunks(F::LANES).enumerate() {
            let p = Lanes::<F>::from_columns(rays, k * walkers::CHUNK + F::LANES * j, o.len());
            let mut c = Closest::<F>::new(&p);
            let mut d = queue.defer(F::LANES * j);
            if p.valid != 0 {
                walk::<F, V>(v, shapes, &p, &mut c, Some(&mut d));
            }
            let used = d.used;
            // The rays that queued walks, with what their packet found.
            for i in lanes(used) {
                let (sr, inv) = p.single(i);
                queue.subjects[F::LANES * j + i] = Subject {
                    ray: p.ray(i),
                    sr,
                    inv,
                    best: c.best(i),
                    found: None,
                    blocked: false,
                };
            }
            packets.push((c, used));
        }
        queue.run::<V, u64>(v, shapes, chunk.len());
        for (j, (o, (c, used))) in chunk.chunks_mut(F::LANES).zip(&mut packets).enumerate() {
            for i in lanes(*used) {
                if let Some(f) = queue.subjects[F::LANES * j + i].found {
                    c.set(i, f);
                }
            }
            c.write_raw(v.first, o);
        }
    }
    queue.give_back();
}
