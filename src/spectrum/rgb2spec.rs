//! RGB → spectrum uplift (stub API; implemented by the spectral-data work).

/// s(λ) = sigmoid(c0 λ² + c1 λ + c2), λ in nm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SigmoidPolynomial {
    pub c0: f32,
    pub c1: f32,
    pub c2: f32,
}
impl SigmoidPolynomial {
    pub fn eval(&self, _lambda: f32) -> f32 {
        todo!()
    }
}
/// Coefficients for a linear-sRGB reflectance in [0, 1]³.
pub fn rgb_to_sigmoid(_rgb: [f32; 3]) -> SigmoidPolynomial {
    todo!()
}
