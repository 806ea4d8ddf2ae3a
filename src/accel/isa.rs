//! Instruction-set variants of the traversal, chosen at run time.
//!
//! [`super::traverse`] is written once with the portable lanes of [`super::simd`] and compiled
//! here three times: for AVX-512 (with VL, BW, DQ: 8-lane compares into mask registers), for
//! AVX2 + FMA, and for the target's baseline (SSE2 on x86-64, NEON on aarch64, scalar
//! elsewhere). [`Isa::best`] picks the widest the CPU supports (`is_x86_feature_detected!`);
//! a [`super::Bvh`] uses it unless told otherwise ([`super::Bvh::set_isa`]), which is how the
//! tests run every variant and check that all give identical hits. The variants compute the
//! same operations in the same order, so their results are bit-identical.
use super::simd::{Pair8, Vec8};
use super::traverse::{self, Found, View};
use crate::math::Ray;
use crate::shape::Shape;

/// An instruction-set variant of the traversal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Isa {
    /// The compilation target's baseline (no run-time detection).
    Baseline,
    /// x86-64 with AVX2, FMA, BMI1/2, LZCNT and POPCNT.
    Avx2,
    /// x86-64 with AVX-512 F/VL/BW/DQ and the AVX2 set.
    Avx512,
}

impl Isa {
    /// Every variant, narrowest first.
    pub const ALL: [Isa; 3] = [Isa::Baseline, Isa::Avx2, Isa::Avx512];

    /// Whether this CPU can run the variant.
    pub fn supported(self) -> bool {
        match self {
            Isa::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => {
                is_x86_feature_detected!("avx2")
                    && is_x86_feature_detected!("fma")
                    && is_x86_feature_detected!("bmi1")
                    && is_x86_feature_detected!("bmi2")
                    && is_x86_feature_detected!("lzcnt")
                    && is_x86_feature_detected!("popcnt")
            }
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => {
                Isa::Avx2.supported()
                    && is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512vl")
                    && is_x86_feature_detected!("avx512bw")
                    && is_x86_feature_detected!("avx512dq")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The widest supported variant.
    pub fn best() -> Isa {
        *Isa::ALL
            .iter()
            .rev()
            .find(|i| i.supported())
            .unwrap_or(&Isa::Baseline)
    }

    /// Lower-case name (`baseline`, `avx2`, `avx512`).
    pub fn name(self) -> &'static str {
        match self {
            Isa::Baseline => "baseline",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }
}

/// Generates, for one traversal function, the baseline version, the two x86 variants and a
/// dispatcher `$name(isa, ...)`. The caller guarantees `isa.supported()`.
macro_rules! variants {
    ($name:ident, $($body:ident)::+, ($($arg:ident: $ty:ty),*) -> $ret:ty) => {
        #[inline]
        pub fn $name(isa: Isa, $($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            {
                use super::order::Avx8k;
                use super::simd::Avx8;
                #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
                fn avx2($($arg: $ty),*) -> $ret {
                    $($body)::+::<Avx8>($($arg),*)
                }
                #[target_feature(
                    enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi1,bmi2,lzcnt,popcnt"
                )]
                fn avx512($($arg: $ty),*) -> $ret {
                    $($body)::+::<Avx8k>($($arg),*)
                }
                match isa {
                    // SAFETY: `Bvh` only stores a supported `Isa` (checked in `set_isa` and
                    // `Isa::best`).
                    Isa::Avx512 => return unsafe { avx512($($arg),*) },
                    Isa::Avx2 => return unsafe { avx2($($arg),*) },
                    Isa::Baseline => {}
                }
            }
            #[inline(never)]
            fn baseline($($arg: $ty),*) -> $ret {
                $($body)::+::<Pair8>($($arg),*)
            }
            let _ = isa;
            baseline($($arg),*)
        }
    };
}

variants!(closest, traverse::closest, (v: View, shapes: &[Shape], ray: &Ray) -> Option<Found>);
variants!(any, traverse::any, (v: View, shapes: &[Shape], ray: &Ray) -> bool);

/// Closest hits of a batch of rays (one dispatch for the batch).
#[inline(always)]
fn closest_batch<V: Vec8>(v: View, shapes: &[Shape], rays: &[Ray], out: &mut [Option<Found>]) {
    for (r, o) in rays.iter().zip(out) {
        *o = traverse::closest::<V>(v, shapes, r);
    }
}

/// Any-hit results of a batch of rays.
#[inline(always)]
fn any_batch<V: Vec8>(v: View, shapes: &[Shape], rays: &[Ray], out: &mut [bool]) {
    for (r, o) in rays.iter().zip(out) {
        *o = traverse::any::<V>(v, shapes, r);
    }
}

variants!(closest_n, closest_batch, (v: View, shapes: &[Shape], rays: &[Ray], out: &mut [Option<Found>]) -> ());
variants!(any_n, any_batch, (v: View, shapes: &[Shape], rays: &[Ray], out: &mut [bool]) -> ());

/// Generates, for one packet traversal function of [`super::packet`], a dispatcher
/// `$name(isa, ...)` that cuts the batch into packets of the lanes' width: sixteen rays with
/// AVX-512, eight with AVX2; the baseline traces ray by ray (`$fallback`). The caller
/// guarantees `isa.supported()`.
macro_rules! packets {
    ($name:ident, $($body:ident)::+, $fallback:ident, $out:ty) => {
        #[inline]
        pub fn $name(isa: Isa, v: View, shapes: &[Shape], rays: &[Ray], out: &mut [$out]) {
            assert_eq!(rays.len(), out.len());
            #[cfg(target_arch = "x86_64")]
            {
                use super::order::Avx8k;
                use super::simd::Avx8;
                use crate::simd::{F16, F8};
                #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
                fn avx2(v: View, shapes: &[Shape], rays: &[Ray], out: &mut [$out]) {
                    for (r, o) in rays.chunks(8).zip(out.chunks_mut(8)) {
                        $($body)::+::<F8, Avx8>(v, shapes, r, o);
                    }
                }
                #[target_feature(
                    enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi1,bmi2,lzcnt,popcnt"
                )]
                fn avx512(v: View, shapes: &[Shape], rays: &[Ray], out: &mut [$out]) {
                    for (r, o) in rays.chunks(16).zip(out.chunks_mut(16)) {
                        $($body)::+::<F16, Avx8k>(v, shapes, r, o);
                    }
                }
                match isa {
                    // SAFETY: `Bvh` only stores a supported `Isa` (checked in `set_isa` and
                    // `Isa::best`).
                    Isa::Avx512 => return unsafe { avx512(v, shapes, rays, out) },
                    Isa::Avx2 => return unsafe { avx2(v, shapes, rays, out) },
                    Isa::Baseline => {}
                }
            }
            $fallback(Isa::Baseline, v, shapes, rays, out)
        }
    };
}

packets!(
    closest_packets,
    super::packet::closest,
    closest_n,
    Option<Found>
);
packets!(any_packets, super::packet::any, any_n, bool);
packets!(
    closest_packets_raw,
    super::packet::closest_raw,
    closest_raw_n,
    Option<super::RawHit>
);

/// The baseline of [`closest_packets_raw`]: ray by ray, each hit named by [`super::bvh::hit`].
fn closest_raw_n(
    isa: Isa,
    v: View,
    shapes: &[Shape],
    rays: &[Ray],
    out: &mut [Option<super::RawHit>],
) {
    let mut raw = [None; 64];
    for (rs, os) in rays.chunks(64).zip(out.chunks_mut(64)) {
        let raw = &mut raw[..rs.len()];
        closest_n(isa, v, shapes, rs, raw);
        for (o, r) in os.iter_mut().zip(raw.iter()) {
            *o = r.map(|f| super::RawHit {
                hit: super::bvh::hit(v.first, f),
                block: f.block,
                lane: f.lane,
            });
        }
    }
}

/// Generates a dispatcher `$name(isa, v, shapes, rays: &RayColumns, out)` that hands the
/// whole batch to the packet function `$body(v, shapes, rays, out)`, compiled for the lanes'
/// width (sixteen rays to a packet with AVX-512, eight with AVX2); the baseline takes the rays
/// one by one through `$fallback`. The caller guarantees `isa.supported()`.
macro_rules! column_packets {
    ($name:ident, $($body:ident)::+, $fallback:ident, $out:ty) => {
        #[inline]
        pub fn $name(
            isa: Isa,
            v: View,
            shapes: &[Shape],
            rays: &super::packet::RayColumns,
            out: &mut [$out],
        ) {
            assert_eq!(rays.n, out.len());
            #[cfg(target_arch = "x86_64")]
            {
                use super::packet::RayColumns;
                use super::order::Avx8k;
                use super::simd::Avx8;
                use crate::simd::{F16, F8};
                #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
                fn avx2(v: View, shapes: &[Shape], rays: &RayColumns, out: &mut [$out]) {
                    $($body)::+::<F8, Avx8>(v, shapes, rays, out);
                }
                #[target_feature(
                    enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi1,bmi2,lzcnt,popcnt"
                )]
                fn avx512(v: View, shapes: &[Shape], rays: &RayColumns, out: &mut [$out]) {
                    $($body)::+::<F16, Avx8k>(v, shapes, rays, out);
                }
                match isa {
                    // SAFETY: `Bvh` only stores a supported `Isa` (checked in `set_isa` and
                    // `Isa::best`).
                    Isa::Avx512 => return unsafe { avx512(v, shapes, rays, out) },
                    Isa::Avx2 => return unsafe { avx2(v, shapes, rays, out) },
                    Isa::Baseline => {}
                }
            }
            let all: Vec<Ray> = (0..rays.n).map(|i| rays.ray(i)).collect();
            $fallback(isa, v, shapes, &all, out);
        }
    };
}

column_packets!(
    closest_columns_raw,
    super::packet::closest_raw_batch,
    closest_raw_n,
    Option<super::RawHit>
);
column_packets!(any_columns, super::packet::any_batch, any_n, bool);
