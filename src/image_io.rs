//! Image reading and writing: EXR, Radiance HDR, PNG (stub; implemented by the lights work).
