//! Walking a tile's polygon list (a subpass's run of it): runs of consecutive primitives of
//! one draw, each handed to the draw's pipeline in one call — in submission order with early-Z
//! ([`render_in_order`]), or with hidden-surface removal ([`render_hsr`], the algorithm is
//! described in `depth::hsr`).

use crate::binning::frame_data::FrameData;
use crate::depth::hsr::{HsrMode, Visibility};
use crate::pass::Draw;
use crate::pixel::primitive::{FragmentTally, Mode, PrimitiveRun};
use crate::raster::PixelRect;
use crate::raster::target::RenderTarget;

/// Runs of list positions that are consecutive and whose primitives share a state record
/// (one draw), from `positions` (ascending): `(first, count, state)`. The states come from
/// the frame data's state starts, not the primitive records (a cache miss each). Every walk over a tile's list
/// by draw goes through here: the whole list in order ([`render_in_order`], HSR's pass one) or
/// the positions that own samples after HSR's pass one (`shade_segment`).
fn draw_runs<'a>(
    positions: impl Iterator<Item = usize> + 'a,
    list: &'a [u32],
    frame: &'a FrameData,
) -> impl Iterator<Item = (usize, usize, u32)> + 'a {
    let mut states = frame.state_cursor();
    let mut positions = positions.peekable();
    std::iter::from_fn(move || {
        let first = positions.next()?;
        let state = states.state_of(list[first]);
        let mut count = 1;
        while positions.next_if(|&p| p == first + count && states.state_of(list[p]) == state).is_some() {
            count += 1;
        }
        Some((first, count, state))
    })
}

/// Hands the run `first..first + count` of `list` (one draw's primitives) to its pipeline.
fn rasterize_run(
    (first, count, state): (usize, usize, u32),
    list: &[u32],
    frame: &FrameData,
    draws: &[Draw],
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
    mode: &mut Mode,
) {
    let state = &frame.states()[state as usize];
    tally.draw = state.draw as usize;
    let stride = if state.flat_only { 0 } else { state.varying_count as usize };
    let run =
        PrimitiveRun::entries(frame.primitives(), frame.varyings(), &list[first..first + count], first as u32, stride);
    draws[state.draw as usize].pipeline.object.rasterize(&run, target, tally, mode);
}

/// Renders a tile's list in submission order (early-Z where the pipeline allows it).
pub fn render_in_order(
    list: &[u32],
    frame: &FrameData,
    draws: &[Draw],
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
) {
    for run in draw_runs(0..list.len(), list, frame) {
        rasterize_run(run, list, frame, draws, target, tally, &mut Mode::InOrder);
    }
}

/// Renders a tile's polygon list with hidden-surface removal (see the module docs).
pub fn render_hsr(
    list: &[u32],
    frame: &FrameData,
    draws: &[Draw],
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
    visibility: &mut Visibility,
    tile: &PixelRect,
) {
    let mut segment: Option<usize> = None;
    for run in draw_runs(0..list.len(), list, frame) {
        let (first, _, state) = run;
        match frame.states()[state as usize].hsr {
            HsrMode::Deferred { claims } => {
                if segment.is_none() {
                    visibility.reset(tile);
                    segment = Some(first);
                }
                rasterize_run(run, list, frame, draws, target, tally, &mut Mode::Resolve { visibility, claims });
            }
            HsrMode::InOrder(reason) => {
                if let Some(start) = segment.take() {
                    shade_segment(list, start..first, frame, draws, target, tally, visibility);
                }
                let before = tally.counters.fragments_rasterized;
                rasterize_run(run, list, frame, draws, target, tally, &mut Mode::InOrder);
                tally.counters.hsr_fallback.add(reason, tally.counters.fragments_rasterized - before);
            }
        }
    }
    if let Some(start) = segment {
        shade_segment(list, start..list.len(), frame, draws, target, tally, visibility);
    }
}

/// Pass two of a segment: shade each primitive that still owns samples, in list order, runs of
/// consecutive owners of one draw in one call.
fn shade_segment(
    list: &[u32],
    segment: std::ops::Range<usize>,
    frame: &FrameData,
    draws: &[Draw],
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
    visibility: &mut Visibility,
) {
    let shaded_before = tally.counters.fragments_shaded;
    visibility.mark_owners(segment.start as u32, segment.len());
    let visibility = &*visibility;
    for run in draw_runs(visibility.owners().map(|o| o as usize), list, frame) {
        rasterize_run(run, list, frame, draws, target, tally, &mut Mode::Shade { visibility });
    }
    let shaded = tally.counters.fragments_shaded - shaded_before;
    tally.counters.fragments_hsr_killed += tally.hsr_candidates.saturating_sub(shaded);
    tally.hsr_candidates = 0;
}
