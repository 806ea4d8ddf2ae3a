//! The pieces a pass's tiles are rendered in ([`work_units`]), and the bookkeeping
//! ([`Book`]) that keeps a stopped or checkpointed film holding whole passes per tile when a
//! tile is rendered in pieces: the first piece of a tile to start decides for all of them
//! whether the tile's pass runs, and the render knows how many tiles are half added.
use super::TILE;
use crate::scene::Scene;
use std::sync::atomic::{AtomicU8, Ordering};

/// Images of fewer tiles than this have each tile's passes rendered in quarters
/// ([`work_units`]): a 96×96 image has nine tiles, and two threads taking them in turn leave
/// one of them idle for a tile at the end of every pass (the thin-film sphere at 96²: 1.055×
/// as fast in quarters). At 256² (64 tiles) the Cornell box gained 2 % and the 1M-triangle
/// mesh nothing; at 640×360 (240 tiles) the built-in scene nothing. A function of the image
/// size alone, so that a render resumed on another number of threads cuts its passes the same
/// way.
pub(super) const SPLIT_BELOW: usize = 128;

/// A piece of a tile's pass: the pixels from `corner` to `far` (exclusive) of tile `tile` of
/// the pass's list, from sample `from` on.
pub(super) struct Unit {
    pub tile: usize,
    pub corner: (u32, u32),
    pub far: (u32, u32),
    pub from: u32,
}

/// The pieces the pass's tiles `todo` are rendered in: each tile whole, or with `split` its
/// quarters (those holding pixels), in tile order.
pub(super) fn work_units(scene: &Scene, todo: &[((u32, u32), u32)], split: bool) -> Vec<Unit> {
    let mut out = Vec::with_capacity(todo.len() * if split { 4 } else { 1 });
    for (tile, &((x0, y0), from)) in todo.iter().enumerate() {
        let (x1, y1) = ((x0 + TILE).min(scene.width), (y0 + TILE).min(scene.height));
        if !split {
            out.push(Unit {
                tile,
                corner: (x0, y0),
                far: (x1, y1),
                from,
            });
            continue;
        }
        let half = TILE / 2;
        for (qy0, qy1) in [(y0, (y0 + half).min(y1)), ((y0 + half).min(y1), y1)] {
            for (qx0, qx1) in [(x0, (x0 + half).min(x1)), ((x0 + half).min(x1), x1)] {
                if qx0 < qx1 && qy0 < qy1 {
                    out.push(Unit {
                        tile,
                        corner: (qx0, qy0),
                        far: (qx1, qy1),
                        from,
                    });
                }
            }
        }
    }
    out
}

/// Per tile of a pass: whether its pass was begun or given up, by the first of its pieces to
/// start, and how many of its pieces are still to be added.
pub(super) struct Book {
    /// 0: undecided, 1: begun, 2: given up.
    state: Vec<AtomicU8>,
    pieces: Vec<u8>,
    left: Vec<AtomicU8>,
}

impl Book {
    /// For `tiles` tiles cut into `units`.
    pub(super) fn new(tiles: usize, units: &[Unit]) -> Book {
        let mut pieces = vec![0u8; tiles];
        for u in units {
            pieces[u.tile] += 1;
        }
        Book {
            state: (0..tiles).map(|_| AtomicU8::new(0)).collect(),
            left: pieces.iter().map(|&c| AtomicU8::new(c)).collect(),
            pieces,
        }
    }

    /// Whether a piece of `tile` is to be rendered: its tile was begun by another piece, or
    /// this one begins it because the render is not stopping (`quit` false). A tile's pieces
    /// all run or none does.
    pub(super) fn start(&self, tile: usize, quit: bool) -> bool {
        let want = if quit { 2 } else { 1 };
        let fate = self.state[tile]
            .compare_exchange(0, want, Ordering::AcqRel, Ordering::Acquire)
            .map_or_else(|v| v, |_| want);
        fate == 1
    }

    /// Records a piece of `tile` as added to the film; returns the change in the number of
    /// half-added tiles (+1 for a tile's first of several pieces, −1 for its last).
    pub(super) fn added(&self, tile: usize) -> isize {
        let before = self.left[tile].fetch_sub(1, Ordering::AcqRel);
        let all = self.pieces[tile];
        match (before == all, before == 1) {
            _ if all == 1 => 0,
            (true, _) => 1,
            (_, true) => -1,
            _ => 0,
        }
    }
}
