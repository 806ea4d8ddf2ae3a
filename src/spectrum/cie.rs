//! CIE 1931 2° colour-matching functions, the D65 illuminant and XYZ ↔ linear sRGB.
//! (stub API; implemented by the spectral-data work)

/// ∫ ȳ(λ) dλ over 360–830 nm.
pub const CIE_Y_INTEGRAL: f32 = 106.856_895;

/// x̄, ȳ, z̄ at `lambda` nm (0 outside 360–830).
pub fn xyz_bar(_lambda: f32) -> [f32; 3] {
    todo!()
}

/// D65 normalised so that ∫ D65·ȳ dλ / CIE_Y_INTEGRAL = 1.
pub fn d65(_lambda: f32) -> f32 {
    todo!()
}

/// XYZ → linear sRGB (D65 white).
pub fn xyz_to_linear_srgb(_xyz: [f32; 3]) -> [f32; 3] {
    todo!()
}
