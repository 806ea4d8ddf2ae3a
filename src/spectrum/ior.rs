//! Named indices of refraction (placeholder API; filled in by the spectral-data work).
