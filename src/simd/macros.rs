//! The shapes the x86 lane types share, written once as macros: an operator trait implemented
//! by one intrinsic on the wrapped registers, and the comparisons of [`super::Float`] by one
//! compare intrinsic taking its predicate as a constant. Each expands to `#[inline(always)]`
//! methods, the same code as written out by hand.

/// `impl $tr for $t` by the intrinsic `$intr` on the two wrapped registers; with `$atr, $af`
/// also the assigning operator through it.
macro_rules! binop {
    ($t:ident, $tr:ident, $f:ident, $intr:ident) => {
        impl $tr for $t {
            type Output = $t;
            #[inline(always)]
            fn $f(self, o: $t) -> $t {
                unsafe { $t($intr(self.0, o.0)) }
            }
        }
    };
    ($t:ident, $tr:ident, $f:ident, $intr:ident, $atr:ident, $af:ident) => {
        binop!($t, $tr, $f, $intr);
        impl $atr for $t {
            #[inline(always)]
            fn $af(&mut self, o: $t) {
                *self = $tr::$f(*self, o);
            }
        }
    };
}

/// The comparisons of `Float` (`lt` … `ne`, `is_nan`) inside its `impl`, by `$cmp::<PREDICATE>`
/// on the wrapped registers, wrapped in the mask type `$m`. Ordered predicates, as `<` on
/// `f32` (false with a NaN operand); `ne` unordered, as `!=` (true with a NaN operand).
macro_rules! float_comparisons {
    ($m:ident, $cmp:ident) => {
        float_comparisons!(@ $m, $cmp, lt _CMP_LT_OQ, le _CMP_LE_OQ, gt _CMP_GT_OQ,
            ge _CMP_GE_OQ, eq _CMP_EQ_OQ, ne _CMP_NEQ_UQ);
        #[inline(always)]
        fn is_nan(self) -> $m {
            unsafe { $m($cmp::<_CMP_UNORD_Q>(self.0, self.0)) }
        }
    };
    (@ $m:ident, $cmp:ident, $($f:ident $pred:ident),*) => {
        $(
            #[inline(always)]
            fn $f(self, o: Self) -> $m {
                unsafe { $m($cmp::<$pred>(self.0, o.0)) }
            }
        )*
    };
}

/// Tests: runs `$body` inside a function compiled for AVX2 (`on_avx2!`) or AVX-512
/// (`on_avx512!`) when the CPU has the instruction set, and passes over it otherwise.
#[cfg(test)]
macro_rules! on_isa {
    ($features:literal, $supported:expr, $body:block) => {
        if $supported {
            #[target_feature(enable = $features)]
            fn run() $body
            // SAFETY: the features were detected above.
            unsafe { run() }
        }
    };
}
#[cfg(test)]
macro_rules! on_avx2 {
    ($body:block) => {
        on_isa!(
            "avx2,fma",
            is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            $body
        )
    };
}
#[cfg(test)]
macro_rules! on_avx512 {
    ($body:block) => {
        on_isa!(
            "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma",
            crate::accel::Isa::Avx512.supported(),
            $body
        )
    };
}

/// Methods that are one intrinsic on the wrapped registers, the result wrapped in its type:
/// `fn f(self) -> R = intrinsic;`, `fn f(self, o: T) -> R = intrinsic;` (binary, `self`
/// first) and `fn f(x: T) -> R = intrinsic;` (a conversion from another lane type).
macro_rules! intrinsics {
    () => {};
    (fn $f:ident(self) -> $r:ident = $intr:ident; $($rest:tt)*) => {
        #[inline(always)]
        fn $f(self) -> $r {
            unsafe { $r($intr(self.0)) }
        }
        intrinsics!($($rest)*);
    };
    (fn $f:ident(self, $o:ident: $t:ty) -> $r:ident = $intr:ident; $($rest:tt)*) => {
        #[inline(always)]
        fn $f(self, $o: $t) -> $r {
            unsafe { $r($intr(self.0, $o.0)) }
        }
        intrinsics!($($rest)*);
    };
    (fn $f:ident($x:ident: $t:ty) -> $r:ident = $intr:ident; $($rest:tt)*) => {
        #[inline(always)]
        fn $f($x: $t) -> $r {
            unsafe { $r($intr($x.0)) }
        }
        intrinsics!($($rest)*);
    };
}
