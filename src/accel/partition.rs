//! Partitions of the SAH build's ranges ([`super::build`]): in place, without branches, and
//! for long ranges on all threads, in an order that does not depend on the thread count.
use super::build::{Ref, BIN_CHUNK};
use glam::{BVec4A, Vec4};
use rayon::prelude::*;

/// Partitions `refs` in place, those for which `left` holds first; returns their number and
/// the centroid bounds (of `lo + hi`) of both sides: left low, left high, right low, right
/// high. Without branches: which side a ref goes to is as good as random, and a mispredicted
/// branch per ref cost more than the swap that every ref now makes (Lomuto's scheme: refs
/// before `i` are the left side so far).
#[inline(always)]
pub(super) fn partition(refs: &mut [Ref], left: &impl Fn(&Ref) -> bool) -> (usize, [Vec4; 4]) {
    let inf = Vec4::splat(f32::INFINITY);
    let (mut lclo, mut lchi, mut rclo, mut rchi) = (inf, -inf, inf, -inf);
    let mut i = 0usize;
    for j in 0..refs.len() {
        let c = refs[j].c2();
        let l = left(&refs[j]);
        let m = BVec4A::splat(l);
        lclo = Vec4::select(m, lclo.min(c), lclo);
        lchi = Vec4::select(m, lchi.max(c), lchi);
        rclo = Vec4::select(m, rclo, rclo.min(c));
        rchi = Vec4::select(m, rchi, rchi.max(c));
        refs.swap(i, j);
        i += l as usize;
    }
    (i, [lclo, lchi, rclo, rchi])
}

/// [`partition`] of a long range on all threads: chunks of [`BIN_CHUNK`] refs are partitioned
/// each on its own, in parallel, leaving `[left₀ right₀][left₁ right₁]…`; then the right refs
/// that lie before the total left count change places with the left refs that lie after it,
/// in order. The chunks do not depend on the thread count, so neither does the order. (The
/// top node of a mesh in a room peels the walls off the mesh one split at a time, each a pass
/// over the whole mesh: one thread partitioned while the other waited.)
pub(super) fn partition_parallel(
    refs: &mut [Ref],
    left: &(impl Fn(&Ref) -> bool + Sync),
) -> (usize, [Vec4; 4]) {
    let parts: Vec<(usize, [Vec4; 4])> = refs
        .par_chunks_mut(BIN_CHUNK)
        .map(|c| partition(c, left))
        .collect();
    let inf = Vec4::splat(f32::INFINITY);
    let mut bounds = [inf, -inf, inf, -inf];
    for (_, b) in &parts {
        bounds = [
            bounds[0].min(b[0]),
            bounds[1].max(b[1]),
            bounds[2].min(b[2]),
            bounds[3].max(b[3]),
        ];
    }
    let total: usize = parts.iter().map(|p| p.0).sum();
    // Misplaced runs, in order: right refs before `total`, left refs from `total` on.
    let (mut early, mut late) = (Vec::new(), Vec::new());
    for (k, &(l, _)) in parts.iter().enumerate() {
        let start = k * BIN_CHUNK;
        let end = (start + BIN_CHUNK).min(refs.len());
        let (lefts, rights) = (start..start + l, start + l..end);
        if rights.start < total {
            early.push(rights.start..rights.end.min(total));
        }
        if lefts.end > total {
            late.push(lefts.start.max(total)..lefts.end);
        }
    }
    let mut late = late.into_iter().flatten();
    for a in early.into_iter().flatten() {
        let b = late.next().expect("as many misplaced on each side");
        refs.swap(a, b);
    }
    debug_assert!(late.next().is_none());
    (total, bounds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pcg32;

    #[test]
    fn parallel_partition_puts_the_same_refs_on_each_side() {
        // Ranges of several chunks (and a partial last one) with sides of every balance, from
        // none to all: the same count, the same refs on each side and the same centroid bounds
        // as the one-thread partition, and the same order on 1 and 3 threads.
        let mut rng = Pcg32::new(21, 4);
        let n = 3 * BIN_CHUNK + 1234;
        let refs: Vec<Ref> = (0..n)
            .map(|i| {
                let lo = Vec4::new(rng.next_f32(), rng.next_f32(), rng.next_f32(), 0.0) * 8.0;
                Ref {
                    lo: Vec4::new(lo.x, lo.y, lo.z, f32::from_bits(i as u32)),
                    hi: lo + Vec4::new(rng.next_f32(), rng.next_f32(), rng.next_f32(), 0.0),
                }
            })
            .collect();
        for cut in [-1.0, 0.05, 4.0, 8.0, 15.9, 100.0] {
            let left = |r: &Ref| r.c2().y < cut;
            let mut a = refs.clone();
            let (na, ba) = partition(&mut a, &left);
            let sorted = |v: &[Ref]| {
                let mut ids: Vec<u32> = v.iter().map(Ref::id).collect();
                ids.sort_unstable();
                ids
            };
            let mut orders = Vec::new();
            for threads in [1, 3] {
                let mut b = refs.clone();
                let (nb, bb) = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| partition_parallel(&mut b, &left));
                assert_eq!(nb, na, "cut {cut}");
                assert_eq!(bb, ba, "cut {cut}");
                assert!(b[..nb].iter().all(left) && !b[nb..].iter().any(left));
                assert_eq!(sorted(&b[..nb]), sorted(&a[..na]));
                assert_eq!(sorted(&b[nb..]), sorted(&a[na..]));
                orders.push(b.iter().map(Ref::id).collect::<Vec<_>>());
            }
            assert_eq!(orders[0], orders[1], "cut {cut}");
        }
    }
}
