//! Frame timing: how frame times were measured, the times of a headless render, their
//! median, and the GPU timestamp queries around a render pass (shared by [`super::Headless`]
//! and the viewer).

use super::headless::map_read;
use crate::gpu::{GpuContext, GpuError};

/// How frame times were measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimingSource {
    /// GPU timestamps written at the start and end of the render pass.
    GpuTimestamps,
    /// Wall clock from submitting the frame to the device reporting it done (includes
    /// submission overhead; used when the device has no timestamp queries).
    WallClock,
}

impl std::fmt::Display for TimingSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::GpuTimestamps => "GPU timestamps around the render pass",
            Self::WallClock => "wall clock from submit to completion (no timestamp queries)",
        })
    }
}

/// Per-frame times of a headless render.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTiming {
    pub source: TimingSource,
    /// Milliseconds per timed frame (after one untimed warm-up frame).
    pub frame_ms: Vec<f64>,
}

impl FrameTiming {
    /// The median of [`FrameTiming::frame_ms`] (mean of the middle two for an even count).
    pub fn median_ms(&self) -> f64 {
        median(&self.frame_ms).unwrap_or(f64::NAN)
    }
}

/// The median of `values` (mean of the middle two for an even count), `None` when empty:
/// the one statistic every timing of the runtime and the report quotes.
pub fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    Some(if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    })
}

/// them back: used by [`Headless::render`](super::Headless::render) (read at once) and the
/// viewer (read when mapped).
pub(crate) struct PassTimestamps {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    /// `MAP_READ` copy of the two ticks, filled by [`PassTimestamps::resolve`].
    pub readback: wgpu::Buffer,
    /// Nanoseconds per tick.
    period_ns: f64,
}

impl PassTimestamps {
    pub fn new(context: &GpuContext, label: &str) -> Self {
        let device = &context.device;
        // Two u64 ticks: 16 bytes, a multiple of the 8-byte resolve alignment.
        let buffer = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 16,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(label),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolved: buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            readback: buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
            period_ns: context.timestamp_period() as f64,
        }
    }

    /// The pass's timestamp writes.
    pub fn writes(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    /// Records the resolve of the queries into `readback` (after the pass).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..2, &self.resolved, 0);
        encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.readback, 0, 16);
    }

    /// The pass's duration in milliseconds from the mapped contents of `readback`.
    pub fn elapsed_ms(&self, readback: &[u8]) -> f64 {
        let tick = |k: usize| u64::from_le_bytes(std::array::from_fn(|i| readback[8 * k + i]));
        // A pass can straddle a counter wrap; end < start is read modulo 2^64.
        tick(1).wrapping_sub(tick(0)) as f64 * self.period_ns * 1e-6
    }

    /// Maps `readback`, waiting for the device, and returns the duration in milliseconds.
    pub(super) fn read(&self, context: &GpuContext) -> Result<f64, GpuError> {
        Ok(self.elapsed_ms(&map_read(context, &self.readback)?))
    }
}
