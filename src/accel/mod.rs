//! Ray-intersection acceleration (stub; implemented by the geometry work).
