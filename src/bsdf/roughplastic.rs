//! (stub; implemented by the BSDF work)
use super::{BsdfSample, BxdfFlags, TransportMode};
use crate::math::{Pcg32, Vec2, Vec3};
use crate::spectrum::SampledSpectrum;

#[derive(Clone, Debug)]
pub struct RoughPlasticBxdf {}
impl RoughPlasticBxdf {
    pub fn flags(&self) -> BxdfFlags {
        todo!()
    }
    pub fn f(
        &self,
        _wo: Vec3,
        _wi: Vec3,
        _mode: TransportMode,
        _rng: &mut Pcg32,
    ) -> SampledSpectrum {
        todo!()
    }
    pub fn sample_f(
        &self,
        _wo: Vec3,
        _uc: f32,
        _u: Vec2,
        _mode: TransportMode,
        _rng: &mut Pcg32,
    ) -> Option<BsdfSample> {
        todo!()
    }
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode, _rng: &mut Pcg32) -> f32 {
        todo!()
    }
}
