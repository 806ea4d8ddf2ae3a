//! Light sources (stub; implemented by the lights work).
