//! Where the wavefront integrator's time goes: the wall-clock time of each step of a round
//! (see the module header of [`super`]), summed over every tile and thread of the process,
//! with the number of path vertices traced and shadow rays cast. Reading it costs seven clock
//! reads per round of up to [`super::POOL`] paths, and one atomic add per step per tile.
//!
//! `ophis render --stats` prints it; [`take`] reads and resets it.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// The steps of a round, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// New paths: wavelengths, filter and lens samples, camera rays.
    Refill,
    /// The closest hits of the pool's rays (and, without environment light, retiring the
    /// paths that escaped).
    Trace,
    /// Ordering the pool by what each path hit.
    Group,
    /// Shading the vertices, in lanes and in the scalar estimator.
    Shade,
    /// Tracing the shadow rays and adding the unoccluded ones' contributions.
    Shadow,
    /// Writing ended paths' values and compacting the pool.
    Retire,
}

impl Stage {
    /// Every stage, in round order.
    pub const ALL: [Stage; 6] = [
        Stage::Refill,
        Stage::Trace,
        Stage::Group,
        Stage::Shade,
        Stage::Shadow,
        Stage::Retire,
    ];

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Refill => "refill",
            Stage::Trace => "trace",
            Stage::Group => "group",
            Stage::Shade => "shade",
            Stage::Shadow => "shadow rays",
            Stage::Retire => "retire",
        }
    }
}

/// Totals since the last [`take`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Seconds spent in each stage ([`Stage::ALL`] order), summed over threads.
    pub seconds: [f64; 6],
    /// Path vertices traced: the rays of [`Stage::Trace`].
    pub rays: u64,
    /// Shadow rays cast.
    pub shadow_rays: u64,
}

impl StageTimes {
    /// Seconds in all stages.
    pub fn total(&self) -> f64 {
        self.seconds.iter().sum()
    }
}

/// Nanoseconds per stage, then rays, then shadow rays.
static TOTALS: [AtomicU64; 8] = [const { AtomicU64::new(0) }; 8];

/// The totals of every render since the last call (all threads of the process), reset to zero.
pub fn take() -> StageTimes {
    let mut v = [0u64; 8];
    for (x, t) in v.iter_mut().zip(&TOTALS) {
        *x = t.swap(0, Ordering::Relaxed);
    }
    StageTimes {
        seconds: std::array::from_fn(|k| v[k] as f64 * 1e-9),
        rays: v[6],
        shadow_rays: v[7],
    }
}

/// One tile's stopwatch: [`Clock::lap`] charges the time since the previous lap to a stage.
pub(super) struct Clock {
    last: Instant,
    /// Nanoseconds per stage, then rays, then shadow rays (as `TOTALS`).
    sums: [u64; 8],
}

impl Clock {
    pub fn new() -> Clock {
        Clock {
            last: Instant::now(),
            sums: [0; 8],
        }
    }

    /// Charges the time since the last lap (or since [`Clock::new`]) to `stage`.
    #[inline]
    pub fn lap(&mut self, stage: Stage) {
        let now = Instant::now();
        self.sums[stage as usize] += now.duration_since(self.last).as_nanos() as u64;
        self.last = now;
    }

    /// Counts a round's traced rays and shadow rays.
    #[inline]
    pub fn count(&mut self, rays: usize, shadow_rays: usize) {
        self.sums[6] += rays as u64;
        self.sums[7] += shadow_rays as u64;
    }
}

impl Drop for Clock {
    /// Adds the tile's totals to the process's.
    fn drop(&mut self) {
        for (t, &x) in TOTALS.iter().zip(&self.sums) {
            t.fetch_add(x, Ordering::Relaxed);
        }
    }
}
