//! Single-ray walks taking turns: while one waits for the node or leaf it goes to next, the
//! others compute.
//!
//! A ray that leaves its packet ([`super::alone`]) goes on alone into a subtree; in a mesh of a
//! million triangles (tens of megabytes of nodes and blocks) each node or leaf it visits next
//! is rarely in cache, and a walk cannot go on before it arrives. On trees that large the
//! column queries ([`super::closest_raw_batch`]) queue those walks as [`Job`]s instead of
//! running them at once, and [`run`] advances [`WALKERS`] of them in turn, one node visit or
//! leaf test each, each turn ending with a prefetch of what that walk reads next, which has
//! arrived by its next turn. Kocberber, Falsafi and Grot, "Asynchronous Memory Access
//! Chaining", PVLDB 9(4), 2015, describe this interleaving of pointer chases.
//!
//! A walk does what [`traverse`]'s closest-hit loop does: the same box tests, the children
//! visited nearest first, entries beyond the ray's closest hit so far skipped. A ray's jobs run
//! one after another, in the order its packet queued them (nearest subtree first, mostly), so
//! that the hit one finds prunes the next; its closest hit so far is read at every turn. The
//! closest hit is the first in (parameter, id) order ([`Best`]) whatever order the walks run
//! in, so the answers are the ray-by-ray traversal's, bit for bit.
//!
//! Measured on the 1M-triangle Cornell mesh (`bench/ab.py`, one thread): the render 1.13×
//! as fast (and, with the walks' steps made cheaper by [`Vec8::far_first`], a packet now hands
//! its rays to them sooner: [`super::SWITCH_NODE_QUEUED_EIGHTHS`]); a walk's turn costs about
//! what it costs on a 10k-triangle mesh that fits in cache. Running a ray's walks as they come
//! in the queue rather than one after another made 14 % more node visits. Below
//! [`crate::accel::bvh::INTERLEAVE_BLOCKS`] the queueing is not done: on the Cornell box's
//! spheres it cost 9 %.
//!
//! [`traverse`]: crate::accel::traverse
use crate::accel::block::{widen, Best, RayLanes};
use crate::accel::simd::Vec8;
use crate::accel::traverse::{BoxRay, Found, View, STACK};
use crate::accel::wide::{leaf_range, LEAF};
use crate::math::{Ray, Vec3};
use crate::shape::mesh::ShearedRay;
use crate::shape::Shape;
use crate::simd::Float;
use std::mem::MaybeUninit;

/// Walks advanced in turn (measured on the 1M-triangle mesh: 4 and 16 gained less than 8).
pub const WALKERS: usize = 8;

/// Rays per round of queued walks: the batch is cut into chunks of this many, each chunk's
/// packets walked and then its queued walks run.
pub(super) const CHUNK: usize = 1024;

/// A queued walk: ray `ray` (an index into the [`Subject`]s) through the subtree `node`,
/// which it enters at `near`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Job {
    ray: u32,
    node: u32,
    near: f32,
}

/// A ray the walks serve, with its closest hit so far (the hit its packet found, then the
/// walks' own), or whether something blocks it.
#[derive(Clone, Copy)]
pub(super) struct Subject {
    pub ray: Ray,
    pub sr: ShearedRay,
    pub inv: Vec3,
    pub best: Best,
    pub found: Option<Found>,
    pub blocked: bool,
}

impl Subject {
    /// A placeholder for a ray with no walks (never read).
    const NONE: Subject = Subject {
        ray: Ray {
            o: Vec3::ZERO,
            d: Vec3::Z,
            t_max: 0.0,
        },
        sr: ShearedRay {
            kx: 0,
            ky: 1,
            kz: 2,
            sx: 0.0,
            sy: 0.0,
            sz: 1.0,
        },
        inv: Vec3::ONE,
        best: Best { t: 0.0, id: 0 },
        found: None,
        blocked: false,
    };
}

/// A chunk's queued walks and the rays they serve. One per thread, kept from batch to batch
/// ([`Queue::take`]): allocated anew per batch, its 120 kB of subjects cost 3 % of the
/// 1M-triangle mesh's render in page clearing.
pub(super) struct Queue {
    jobs: Vec<Job>,
    grouped: Vec<Job>,
    groups: Vec<u32>,
    /// Where each ray's group starts (the counting sort's counts).
    start: Vec<u32>,
    pub subjects: Vec<Subject>,
}

thread_local! {
    static QUEUE: std::cell::Cell<Option<Box<Queue>>> = const { std::cell::Cell::new(None) };
}

impl Queue {
    /// This thread's queue (a new one the first time, or while another call holds it).
    pub fn take() -> Box<Queue> {
        QUEUE.with(|q| q.take()).unwrap_or_else(|| {
            Box::new(Queue {
                jobs: Vec::with_capacity(CHUNK),
                grouped: Vec::with_capacity(CHUNK),
                groups: Vec::with_capacity(CHUNK + 1),
                start: Vec::with_capacity(CHUNK + 1),
                subjects: vec![Subject::NONE; CHUNK],
            })
        })
    }

    /// Keeps the queue for this thread's next batch.
    pub fn give_back(self: Box<Queue>) {
        QUEUE.with(|q| q.set(Some(self)));
    }

    /// Where the packet whose first ray is ray `base` of the chunk queues its walks.
    pub fn defer(&mut self, base: usize) -> Defer<'_> {
        Defer {
            jobs: &mut self.jobs,
            base: base as u32,
            used: 0,
        }
    }

    /// Runs the chunk's queued walks (of rays below `n`) with walkers of kind `W` and empties
    /// the queue.
    #[inline(always)]
    pub fn run<V: Vec8, E>(&mut self, v: View, shapes: &[Shape], n: usize)
    where
        for<'s> Walker<'s, V, E>: Walk,
    {
        self.group_by_ray(n);
        run::<V, E>(v, shapes, &mut self.subjects, &self.grouped, &self.groups);
        self.jobs.clear();
    }

    /// The jobs into `grouped`, grouped by ray with each ray's in their order (a counting
    /// sort); `groups` gets the start of each ray's group and the end of the last.
    fn group_by_ray(&mut self, n: usize) {
        let start = &mut self.start;
        start.clear();
        start.resize(n + 1, 0);
        for j in &self.jobs {
            start[j.ray as usize + 1] += 1;
        }
        // Without a branch per ray (whether it queued a walk is a coin toss): every ray
        // writes its group's end one slot on, and the count advances only past those that
        // have a group.
        let mut at = 0;
        self.groups.clear();
        self.groups.resize(n + 1, 0);
        let mut len = 1;
        for s in start.iter_mut().skip(1) {
            at += *s;
            self.groups[len] = at;
            len += (*s != 0) as usize;
            *s = at;
        }
        self.groups.truncate(len);
        // `start[r]` is now the number of jobs of rays below `r`: where ray r's group starts.
        self.grouped.clear();
        self.grouped.resize(
            self.jobs.len(),
            Job {
                ray: 0,
                node: 0,
                near: 0.0,
            },
        );
        for j in &self.jobs {
            let s = &mut start[j.ray as usize];
            self.grouped[*s as usize] = *j;
            *s += 1;
        }
    }
}

/// Where a packet's walk queues the walks of its rays that go on alone.
pub(super) struct Defer<'a> {
    jobs: &'a mut Vec<Job>,
    /// The index of the packet's first ray among the [`Subject`]s.
    base: u32,
    /// The lanes that queued a walk.
    pub used: u32,
}

impl Defer<'_> {
    /// Queues the walks of the rays `active` through `node`, entered at `entry`.
    #[inline(always)]
    pub fn push<F: Float>(&mut self, node: u32, active: u32, entry: F) {
        self.used |= active;
        let mut bits = active;
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            self.jobs.push(Job {
                ray: self.base + i as u32,
                node,
                near: entry.lane(i),
            });
        }
    }
}

/// One walk in progress, with stack entries `E`: (subtree, entry distance) for closest hits,
/// subtrees for occlusion. The stack is borrowed, not owned: the walkers are made anew for
/// every chunk, and a walker owning its 5.5 kB stack was built and then copied into place
/// (the eight of them, 47 kB per chunk of rays, cost ~3 % of the 1M-triangle mesh's trace).
pub(super) struct Walker<'s, V, E> {
    /// The subject's index; [`IDLE`] when the walker has none.
    ray: usize,
    cur: u32,
    sp: usize,
    lanes: RayLanes,
    br: BoxRay<V>,
    stack: &'s mut [MaybeUninit<E>; STACK],
}

/// A closest-hit walk.
pub(super) type Closest<'s, V> = Walker<'s, V, u64>;
/// An occlusion walk: any primitive hit within the ray's extent blocks it.
pub(super) type Any<'s, V> = Walker<'s, V, u32>;

const IDLE: usize = usize::MAX;

impl<'s, V: Vec8, E> Walker<'s, V, E> {
    /// A walker with no walk, using `stack`.
    #[inline(always)]
    fn idle(stack: &'s mut [MaybeUninit<E>; STACK]) -> Self {
        let none = Subject::NONE;
        Walker {
            ray: IDLE,
            cur: 0,
            sp: 0,
            lanes: RayLanes::new(&none.ray, &none.sr),
            br: BoxRay::new(&none.ray, none.inv),
            stack,
        }
    }

    /// Starts `job` for its ray `s`.
    #[inline(always)]
    fn start(&mut self, v: View, s: &Subject, job: &Job) {
        self.ray = job.ray as usize;
        self.cur = job.node;
        self.sp = 0;
        self.lanes = RayLanes::new(&s.ray, &s.sr);
        self.br = BoxRay::new(&s.ray, s.inv);
        v.prefetch(job.node);
    }
}

/// What a kind of walk does at each turn.
pub(super) trait Walk {
    /// One node visit or leaf test, ending with the prefetch of what comes next; false when
    /// the walk is over.
    fn step(&mut self, v: View, shapes: &[Shape], s: &mut Subject) -> bool;
    /// Whether `job` has nothing left to find for its ray `s`.
    fn pruned(s: &Subject, job: &Job) -> bool;
}

impl<V: Vec8> Walk for Closest<'_, V> {
    #[inline(always)]
    fn pruned(s: &Subject, job: &Job) -> bool {
        job.near > widen(s.best.t)
    }

    #[inline(always)]
    fn step(&mut self, v: View, shapes: &[Shape], s: &mut Subject) -> bool {
        let cur = self.cur;
        if cur & LEAF != 0 {
            let (first, n) = leaf_range(cur);
            for (k, b) in v.blocks[first..first + n].iter().enumerate() {
                if let Some((lane, uv)) = b.closest(&self.lanes, &s.ray, &mut s.best, shapes) {
                    s.found = Some(Found {
                        id: s.best.id,
                        t: s.best.t,
                        uv,
                        block: (first + k) as u32,
                        lane: lane as u32,
                    });
                }
            }
        } else {
            let node = &v.nodes[cur as usize];
            let (near, mask) = node.hit(&self.br.o, &self.br.inv_d, s.best.t);
            if mask != 0 {
                // As `traverse`: far first, so that the stack pops the nearest first.
                // SAFETY: the stack has room for eight entries above any `sp` a walk reaches.
                let out = unsafe {
                    &mut *(self.stack.as_mut_ptr().add(self.sp) as *mut [MaybeUninit<u64>; 8])
                };
                let nearest = near.far_first(&node.child, mask, out);
                self.sp += mask.count_ones() as usize - 1;
                self.cur = nearest as u32;
                v.prefetch(self.cur);
                return true;
            }
        }
        while self.sp > 0 {
            self.sp -= 1;
            // SAFETY: slots below the old `sp` were all written by a push.
            let k = unsafe { self.stack[self.sp].assume_init() };
            let (c, t) = (k as u32, f32::from_bits((k >> 32) as u32));
            if t <= widen(s.best.t) {
                self.cur = c;
                v.prefetch(c);
                return true;
            }
        }
        false
    }
}

impl<V: Vec8> Walk for Any<'_, V> {
    #[inline(always)]
    fn pruned(s: &Subject, _: &Job) -> bool {
        s.blocked
    }

    /// As `traverse::any_from`: the first child entered next, the others pushed.
    #[inline(always)]
    fn step(&mut self, v: View, shapes: &[Shape], s: &mut Subject) -> bool {
        let cur = self.cur;
        if cur & LEAF != 0 {
            let (first, n) = leaf_range(cur);
            for b in &v.blocks[first..first + n] {
                if b.any(&self.lanes, &s.ray, shapes) {
                    s.blocked = true;
                    return false;
                }
            }
        } else {
            let node = &v.nodes[cur as usize];
            let (_, mask) = node.hit(&self.br.o, &self.br.inv_d, s.ray.t_max);
            if mask != 0 {
                // SAFETY: the stack has room for eight entries above any `sp` a walk reaches.
                let out = unsafe {
                    &mut *(self.stack.as_mut_ptr().add(self.sp) as *mut [MaybeUninit<u32>; 8])
                };
                self.cur = V::first_and_rest(&node.child, mask, out);
                self.sp += mask.count_ones() as usize - 1;
                v.prefetch(self.cur);
                return true;
            }
        }
        if self.sp == 0 {
            return false;
        }
        self.sp -= 1;
        // SAFETY: slots below the old `sp` were all written by a push.
        self.cur = unsafe { self.stack[self.sp].assume_init() };
        v.prefetch(self.cur);
        true
    }
}

/// Runs `jobs` on `subjects`, [`WALKERS`] rays at a time. `jobs` are grouped by ray, and
/// `groups` holds the start of each group and the end of the last.
#[inline(always)]
fn run<V: Vec8, E>(
    v: View,
    shapes: &[Shape],
    subjects: &mut [Subject],
    jobs: &[Job],
    groups: &[u32],
) where
    for<'s> Walker<'s, V, E>: Walk,
{
    // Uninitialised: no code runs to make them.
    let mut stacks = [const { [const { MaybeUninit::<E>::uninit() }; STACK] }; WALKERS];
    let mut free = stacks.iter_mut();
    let mut walkers: [Walker<V, E>; WALKERS] =
        std::array::from_fn(|_| Walker::idle(free.next().expect("one stack per walker")));
    // Each walker's jobs still to run: the rest of its ray's group.
    let mut rest = [(0u32, 0u32); WALKERS];
    let mut group = 0;
    // The next job of `from .. to` that its ray still needs.
    let next_job = |from: &mut u32, to: u32, subjects: &[Subject]| {
        while *from < to {
            let j = &jobs[*from as usize];
            *from += 1;
            if !Walker::<V, E>::pruned(&subjects[j.ray as usize], j) {
                return Some(j);
            }
        }
        None
    };
    let mut busy = 0;
    loop {
        for (w, r) in walkers.iter_mut().zip(rest.iter_mut()) {
            if w.ray != IDLE {
                if w.step(v, shapes, &mut subjects[w.ray]) {
                    continue;
                }
                busy -= 1;
                w.ray = IDLE;
            }
            // The ray's next job, else the next ray's first.
            loop {
                if let Some(j) = next_job(&mut r.0, r.1, subjects) {
                    w.start(v, &subjects[j.ray as usize], j);
                    busy += 1;
                    break;
                }
                if group + 1 >= groups.len() {
                    break;
                }
                *r = (groups[group], groups[group + 1]);
                group += 1;
            }
        }
        if busy == 0 {
            return;
        }
    }
}
