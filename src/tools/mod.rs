//! Tools that sit above the renderer and use it: nothing in the renderer imports them.

pub mod inspect;
