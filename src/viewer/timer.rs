//! GPU time of the cloth pass from timestamp queries, read back without stalling the frame
//! loop: a few query slots in rotation, each read when the device reports its buffer mapped
//! (a frame or two later). A frame that finds no free slot goes untimed.

use crate::gpu::GpuContext;
use crate::render::PassTimestamps;
use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

/// Slots in rotation: frames in flight plus one being read (the surface allows two frames
/// of latency).
const SLOTS: usize = 3;

const FREE: u8 = 0;
const PENDING: u8 = 1;
const MAPPED: u8 = 2;
const FAILED: u8 = 3;

struct Slot {
    timestamps: PassTimestamps,
    state: Arc<AtomicU8>,
}

/// Timestamps at the start and end of the cloth pass.
pub(super) struct GpuTimer {
    slots: Vec<Slot>,
    /// The slot the frame being recorded uses.
    current: Option<usize>,
}

impl GpuTimer {
    /// A timer when the device has timestamp queries, else `None`.
    pub fn new(context: &GpuContext) -> Option<Self> {
        if !context.timestamps() {
            return None;
        }
        let slots = (0..SLOTS)
            .map(|_| Slot {
                timestamps: PassTimestamps::new(context, "view timestamps"),
                state: Arc::new(AtomicU8::new(FREE)),
            })
            .collect();
        Some(Self {
            slots,
            current: None,
        })
    }

    /// The timestamp writes for this frame's pass, if a slot is free.
    pub fn begin(&mut self) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let index = self
            .slots
            .iter()
            .position(|s| s.state.load(Ordering::Acquire) == FREE)?;
        self.current = Some(index);
        Some(self.slots[index].timestamps.writes())
    }

    /// Records the resolve of this frame's queries (after the pass).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(slot) = self.current.map(|i| &self.slots[i]) {
            slot.timestamps.resolve(encoder);
        }
    }

    /// After the frame's submit: asks for the read-back buffer to be mapped.
    pub fn submitted(&mut self) {
        if let Some(slot) = self.current.take().map(|i| &self.slots[i]) {
            slot.state.store(PENDING, Ordering::Release);
            let state = slot.state.clone();
            slot.timestamps
                .readback
                .slice(..)
                .map_async(wgpu::MapMode::Read, move |result| {
                    state.store(
                        if result.is_ok() { MAPPED } else { FAILED },
                        Ordering::Release,
                    );
                });
        }
    }

    /// Pass durations (milliseconds) of the frames whose timestamps have arrived since the
    /// last call; polls the device without waiting.
    pub fn collect(&mut self, context: &GpuContext) -> Vec<f64> {
        let _ = context.device.poll(wgpu::PollType::Poll);
        let mut times = Vec::new();
        for slot in &self.slots {
            match slot.state.load(Ordering::Acquire) {
                MAPPED => {
                    let readback = &slot.timestamps.readback;
                    if let Ok(view) = readback.slice(..).get_mapped_range() {
                        times.push(slot.timestamps.elapsed_ms(&view));
                    }
                    readback.unmap();
                    slot.state.store(FREE, Ordering::Release);
                }
                FAILED => slot.state.store(FREE, Ordering::Release),
                _ => {}
            }
        }
        times
    }
}
