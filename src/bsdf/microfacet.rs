//! Microfacet distributions (stub; implemented by the BSDF work).
