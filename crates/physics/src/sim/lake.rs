//! The lake off the stone's path (issue 41). With wavy contact off the stone never reads the
//! columns (it meets the ambient surface), so the water's work at the end of each tick — take the
//! tick's face impulses, step O'Brien and Hodgins' grid by the tick — need not happen where and
//! when the stone steps. A deferred lake ([`super::Simulation::defer_lake`]) queues that work in
//! order; [`super::Simulation::take_lake`] hands the grid and the queue out as a [`LakeJob`], which
//! any thread may run, and [`super::Simulation::return_lake`] puts the grid back. The grid then is
//! bit for bit the one a run that stepped it at every tick's end holds: the same deposits, in the
//! same order, between the same steps.

use std::sync::atomic::{AtomicU64, Ordering};

pub use super::water::LakeGeometry;
use super::water::WaterGrid;
use super::PendingLoad;

/// One piece of the water's work, in the order the ticks asked for it.
#[derive(Debug, Clone)]
pub(super) enum LakeOp {
    /// The face impulses handed over (`deposit_load_box` each, in order).
    Deposit(Vec<PendingLoad>),
    /// A tick's end: the grid advances by the tick (s).
    Advance(f64),
}

/// Applies `ops` to `grid` in order.
pub(super) fn apply(grid: &mut WaterGrid, ops: Vec<LakeOp>) {
    for op in ops {
        match op {
            LakeOp::Deposit(loads) => {
                for l in &loads {
                    grid.deposit_load_box(l.x, l.y, l.half, l.impulse, l.horizontal);
                }
            }
            LakeOp::Advance(dt) => grid.advance(dt),
        }
    }
}

/// Tells one hand-out from every other, so a grid goes back only to the run it came from.
static NEXT_KEY: AtomicU64 = AtomicU64::new(1);

/// A fresh hand-out key.
pub(super) fn next_key() -> u64 {
    NEXT_KEY.fetch_add(1, Ordering::Relaxed)
}

/// A deferred lake's grid with the work the ticks queued for it.
#[derive(Debug)]
pub struct LakeJob {
    pub(super) grid: WaterGrid,
    pub(super) ops: Vec<LakeOp>,
    pub(super) key: u64,
}

impl LakeJob {
    /// Does the queued work: each tick's deposits, then its step, in order.
    pub fn run(mut self) -> SteppedLake {
        apply(&mut self.grid, self.ops);
        SteppedLake {
            grid: self.grid,
            key: self.key,
        }
    }
}

/// A lake's grid after its [`LakeJob`] ran, to go back to its run.
#[derive(Debug)]
pub struct SteppedLake {
    pub(super) grid: WaterGrid,
    pub(super) key: u64,
}

impl SteppedLake {
    /// The grid as stepped.
    pub fn grid(&self) -> &WaterGrid {
        &self.grid
    }
}
