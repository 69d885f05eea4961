//! GPU time of the cloth pass from timestamp queries, read back without stalling the frame
//! loop: a few query slots in rotation, each read when the device reports its buffer mapped
//! (a frame or two later). A frame that finds no free slot goes untimed.

use crate::gpu::GpuContext;
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
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    readback: wgpu::Buffer,
    state: Arc<AtomicU8>,
}

/// Timestamps at the start and end of the cloth pass.
pub(super) struct GpuTimer {
    slots: Vec<Slot>,
    /// Nanoseconds per tick.
    period_ns: f64,
    /// The slot the frame being recorded uses.
    current: Option<usize>,
}

impl GpuTimer {
    /// A timer when the device has timestamp queries, else `None`.
    pub fn new(context: &GpuContext) -> Option<Self> {
        if !context.timestamps() {
            return None;
        }
        let device = &context.device;
        let slots = (0..SLOTS)
            .map(|_| Slot {
                queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("view timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                }),
                // Two u64 ticks: 16 bytes, a multiple of the 8-byte resolve alignment.
                resolved: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("view timestamps"),
                    size: 16,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                readback: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("view timestamps read-back"),
                    size: 16,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                state: Arc::new(AtomicU8::new(FREE)),
            })
            .collect();
        Some(Self {
            slots,
            period_ns: context.timestamp_period() as f64,
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
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &self.slots[index].queries,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        })
    }

    /// Records the resolve of this frame's queries (after the pass).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(slot) = self.current.map(|i| &self.slots[i]) {
            encoder.resolve_query_set(&slot.queries, 0..2, &slot.resolved, 0);
            encoder.copy_buffer_to_buffer(&slot.resolved, 0, &slot.readback, 0, 16);
        }
    }

    /// After the frame's submit: asks for the read-back buffer to be mapped.
    pub fn submitted(&mut self) {
        if let Some(slot) = self.current.take().map(|i| &self.slots[i]) {
            slot.state.store(PENDING, Ordering::Release);
            let state = slot.state.clone();
            slot.readback
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
                    if let Ok(view) = slot.readback.slice(..).get_mapped_range() {
                        let ticks: &[u64] = bytemuck::cast_slice(&view);
                        // A pass can straddle a counter wrap; end < start is read modulo 2^64.
                        let ticks = ticks[1].wrapping_sub(ticks[0]);
                        times.push(ticks as f64 * self.period_ns * 1e-6);
                    }
                    slot.readback.unmap();
                    slot.state.store(FREE, Ordering::Release);
                }
                FAILED => slot.state.store(FREE, Ordering::Release),
                _ => {}
            }
        }
        times
    }
}
