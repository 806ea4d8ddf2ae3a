//! Grouping the pool's paths by what they hit, before shading.
//!
//! A chunk of lanes runs the code of every material and surface kind among its lanes
//! ([`super::bsdf::LaneBsdf`], [`super::surface`]): in the Cornell box a few glass and gold
//! hits spread over every chunk made most chunks run the dielectric's and the rough
//! conductor's code for one or two lanes each. [`Pool::group`] orders the pool so that each
//! group of hits ([`super::program::CLASSES`]) fills consecutive chunks. Paths are
//! independent, so their order changes nothing they compute (`tests/wavefront.rs` checks the
//! image bit for bit against the scalar loop); it changes only which paths share a chunk.
//!
//! Moving a path moves ~50 fields, so only the paths out of place move, each exchange putting
//! at least one in place: first Hoare's partition around the most common group (each exchange
//! puts two in place), then the in-place "American flag" pass over the rest (McIlroy, Bostic
//! and McIlroy, "Engineering Radix Sort", Computing Systems 6(1), 1993). A full permutation
//! of every column cost more than the divergence it removed (measured: 10 % of the Cornell
//! box's render, against 15 % saved in shading).

use super::pool::{path_columns, Pool, CAP, POOL};
use super::program::{CLASSES, CLASS_SCALAR};

impl Pool {
    /// Exchanges paths `i` and `j`: every field but `alive` (which shading sets for every
    /// live path) and the hit's spread-out copies (see [`Pool::spread_hits`]).
    fn swap_paths(&mut self, i: usize, j: usize) {
        // Checked once: every column has length CAP.
        assert!(i < CAP && j < CAP);
        macro_rules! sw {
            ($a:expr) => {
                $a.swap(i, j)
            };
        }
        path_columns!(self, sw);
        self.hit.swap(i, j);
    }

    /// Orders the live paths by the group of their hit (`class[shape]`; escaped rays are
    /// shaded by the scalar code, [`CLASS_SCALAR`]), before [`Pool::spread_hits`]: the most
    /// common group first, then the others in group order (see the module header).
    pub fn group(&mut self, class: &[u8]) {
        let n = self.n;
        let mut key = [0u8; POOL];
        let mut count = [0usize; CLASSES];
        for (k, h) in key[..n].iter_mut().zip(&self.hit[..n]) {
            *k = match h {
                None => CLASS_SCALAR,
                Some(h) => class[h.hit.shape as usize],
            };
            count[*k as usize] += 1;
        }
        let major = (0..CLASSES).max_by_key(|&c| (count[c], c)).unwrap_or(0);
        if count[major] == n {
            return;
        }
        let (mut i, mut j) = (0, n);
        loop {
            while i < j && key[i] as usize == major {
                i += 1;
            }
            while i < j && key[j - 1] as usize != major {
                j -= 1;
            }
            if i + 1 >= j {
                break;
            }
            self.swap_paths(i, j - 1);
            key.swap(i, j - 1);
        }
        let mut next = [0usize; CLASSES];
        let mut end = [0usize; CLASSES];
        let mut at = count[major];
        for c in (0..CLASSES).filter(|&c| c != major) {
            next[c] = at;
            at += count[c];
            end[c] = at;
        }
        for c in 0..CLASSES {
            while next[c] < end[c] {
                let i = next[c];
                let k = key[i] as usize;
                if k == c {
                    next[c] += 1;
                } else {
                    // Path i belongs further on: into its group's next free slot.
                    let j = next[k];
                    self.swap_paths(i, j);
                    key.swap(i, j);
                    next[k] += 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::RawHit;
    use crate::math::rng::Pcg32;
    use crate::math::Vec2;
    use crate::shape::Hit;

    /// A pool of `n` paths whose every field is a function of the path's job, hitting
    /// shapes drawn at random (shape 0–5; `None` for an escaped ray).
    fn pool(n: usize, seed: u64) -> Pool {
        let mut p = Pool::new();
        let mut rng = Pcg32::new(seed, 7);
        p.n = n;
        for i in 0..n {
            let j = (i * 7 + 3) as u32;
            let x = j as f32;
            for a in 0..3 {
                p.o[a][i] = x + a as f32;
                p.d[a][i] = x * 2.0 + a as f32;
                p.prev_p[a][i] = x * 3.0 + a as f32;
                p.prev_n[a][i] = x * 4.0 + a as f32;
            }
            for k in 0..4 {
                let y = x * 10.0 + k as f32;
                (p.l[k][i], p.beta[k][i], p.lambda[k][i]) = (y, y + 1.0, y + 2.0);
                (p.wl_pdf[k][i], p.d65[k][i]) = (y + 3.0, y + 4.0);
            }
            (p.t_max[i], p.eta_scale[i], p.prev_pdf[i], p.path_length[i]) =
                (x + 0.5, x + 0.25, x + 0.125, x + 0.75);
            (
                p.env_by_bsdf[i],
                p.specular[i],
                p.depth[i],
                p.null_crossings[i],
            ) = (j + 1, j + 2, j + 3, j + 4);
            (p.pixel_seed[i], p.sample_index[i], p.dim[i], p.job[i]) = (j + 5, j + 6, j + 7, j);
            (p.rng_state[i], p.rng_inc[i]) = (j as u64 * 3, j as u64 * 5);
            let shape = rng.next_u32() % 7;
            p.hit[i] = (shape < 6).then_some(RawHit {
                hit: Hit {
                    t: x,
                    shape,
                    prim: j,
                    uv: Vec2::new(x, -x),
                },
                block: j + 8,
                lane: j % 4,
            });
        }
        p
    }

    /// Every field of the path at `i` is still the function of its job.
    fn consistent(p: &Pool, i: usize) -> bool {
        let j = p.job[i];
        let x = j as f32;
        let mut ok = true;
        for a in 0..3 {
            ok &= p.o[a][i] == x + a as f32 && p.d[a][i] == x * 2.0 + a as f32;
            ok &= p.prev_p[a][i] == x * 3.0 + a as f32 && p.prev_n[a][i] == x * 4.0 + a as f32;
        }
        for k in 0..4 {
            let y = x * 10.0 + k as f32;
            ok &= (p.l[k][i], p.beta[k][i], p.lambda[k][i]) == (y, y + 1.0, y + 2.0);
            ok &= (p.wl_pdf[k][i], p.d65[k][i]) == (y + 3.0, y + 4.0);
        }
        ok &= (p.t_max[i], p.eta_scale[i], p.prev_pdf[i], p.path_length[i])
            == (x + 0.5, x + 0.25, x + 0.125, x + 0.75);
        ok &= (
            p.env_by_bsdf[i],
            p.specular[i],
            p.depth[i],
            p.null_crossings[i],
        ) == (j + 1, j + 2, j + 3, j + 4);
        ok &= (p.pixel_seed[i], p.sample_index[i], p.dim[i]) == (j + 5, j + 6, j + 7);
        ok &= (p.rng_state[i], p.rng_inc[i]) == (j as u64 * 3, j as u64 * 5);
        ok && p.hit[i].is_none_or(|h| {
            h.hit.prim == j && h.hit.t == x && h.hit.uv == Vec2::new(x, -x) && h.block == j + 8
        })
    }

    #[test]
    fn removal_keeps_exactly_the_other_paths_each_whole() {
        let mut rng = Pcg32::new(11, 3);
        for (n, p_gone) in [
            (POOL, 0.15),
            (1000, 0.9),
            (37, 0.5),
            (5, 1.0),
            (8, 0.0),
            (0, 0.5),
        ] {
            for escaped in [false, true] {
                let mut p = pool(n, n as u64 + 9);
                let gone: Vec<u32> = (0..n as u32).filter(|_| rng.next_f32() < p_gone).collect();
                let mut keep: Vec<u32> = (0..n)
                    .filter(|i| !gone.contains(&(*i as u32)))
                    .map(|i| p.job[i])
                    .collect();
                for i in 0..n {
                    p.alive[i] = p.job[i] + 1;
                    if !escaped {
                        // Compaction leaves the hits behind (the next round traces anew).
                        p.hit[i] = None;
                    }
                }
                if escaped {
                    p.remove_escaped(&gone);
                } else {
                    p.compact(&gone);
                }
                assert_eq!(p.n, keep.len());
                for i in 0..p.n {
                    assert!(consistent(&p, i), "a path was torn apart");
                    // What each removal carries besides the path's columns came along too.
                    if escaped {
                        assert!(p.hit[i].is_none_or(|h| h.hit.prim == p.job[i]));
                    } else {
                        assert_eq!(p.alive[i], p.job[i] + 1);
                    }
                }
                let mut got: Vec<u32> = p.job[..p.n].to_vec();
                got.sort();
                keep.sort();
                assert_eq!(got, keep, "{n} paths, {} removed", gone.len());
            }
        }
    }

    #[test]
    fn grouping_moves_whole_paths_into_one_range_per_group() {
        // Shapes 0–5 in groups 3, 1, 1, 0, 8, 6; escaped rays are group 8 too.
        let class = [3u8, 1, 1, 0, 8, 6];
        let key = |p: &Pool, i: usize| p.hit[i].map_or(8, |h| class[h.hit.shape as usize]);
        for (n, seed) in [(POOL, 1), (1000, 2), (37, 3), (1, 4), (0, 5)] {
            let mut p = pool(n, seed);
            let mut before: Vec<(u32, u8)> = (0..n).map(|i| (p.job[i], key(&p, i))).collect();
            p.group(&class);
            assert_eq!(p.n, n);
            assert!((0..n).all(|i| consistent(&p, i)), "a path was torn apart");
            let mut after: Vec<(u32, u8)> = (0..n).map(|i| (p.job[i], key(&p, i))).collect();
            // Each group in one range (the most common first, the others in group order).
            let runs: Vec<u8> = after
                .iter()
                .map(|a| a.1)
                .collect::<Vec<_>>()
                .chunk_by(|a, b| a == b)
                .map(|r| r[0])
                .collect();
            let mut distinct = runs.clone();
            distinct.sort();
            distinct.dedup();
            assert_eq!(runs.len(), distinct.len(), "a group is split: {runs:?}");
            if runs.len() > 1 {
                assert!(runs[1..].windows(2).all(|w| w[0] < w[1]), "{runs:?}");
                let count = |c: u8| before.iter().filter(|b| b.1 == c).count();
                assert!(runs.iter().all(|&c| count(c) <= count(runs[0])), "{runs:?}");
            }
            before.sort();
            after.sort();
            assert_eq!(before, after, "the same paths, each with its own group");
        }
    }
}
