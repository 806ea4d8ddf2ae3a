//! Scene loading and the built scene.

pub mod mitsuba;
