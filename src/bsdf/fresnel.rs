//! Fresnel equations (stub; implemented by the BSDF work).
