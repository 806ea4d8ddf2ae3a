//! (stub; implemented by the geometry work)
