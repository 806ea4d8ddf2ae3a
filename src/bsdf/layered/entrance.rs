//! The first choice of a walk that enters a stack from above: the coat's reflection or its
//! transmission. The coat's own probability P is its reflectance, a few per cent for a
//! dielectric, which suits a bright base; over a dark one almost every transmitted path comes
//! back with a tiny weight and the visible reflection gets a few per cent of the samples. The
//! walk instead picks reflection with P′ = P / (P + (1 − P) A), A the share of the transmitted
//! light that comes back out, which makes the choice proportional to what each branch returns
//! (`Rough::sample_f_weighted`; the density changes with it, so the walk stays unbiased).

use super::walk::{Medium, MAX_INTERFACES};
use crate::bsdf::fresnel::fresnel_dielectric;
use crate::bsdf::Bxdf;

/// [`super::Stack::entrance_weight`]: for a coat of relative index η over a layer of optical depth
/// σt over a Lambertian base of albedo ρ, light crossing the coat reaches the base and back
/// with τ ≈ e^{−3σt} (one pass near the normal, one diffuse), escapes through the coat with
/// e ≈ (1 − F(cos θ = ½))/η² of the diffuse flux (the rest is reflected back down), and so
/// returns A = ρτe / (1 − ρτ(1 − e)) after all the round trips (averages over the
/// wavelengths). Floored at 1/200 so that transmission is always sampled.
pub(super) fn return_estimate(ifs: &[Bxdf; MAX_INTERFACES], n: usize, media: &[Medium]) -> f32 {
    let (Some(eta), Bxdf::Diffuse(base)) = (ifs[0].rough_eta(), &ifs[1]) else {
        return 1.0;
    };
    if n != 2 || media[0].scatters() || !(eta > 0.0) {
        return 1.0;
    }
    let tau = (media[0].sigma_t * -3.0).exp().average();
    let rho = base.r.average().clamp(0.0, 1.0) * tau;
    let e = (1.0 - fresnel_dielectric(0.5, eta)) / (eta * eta);
    let a = rho * e / (1.0 - rho * (1.0 - e));
    if a.is_finite() {
        a.clamp(0.005, 1.0)
    } else {
        1.0
    }
}
