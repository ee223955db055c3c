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

/// The runs of `list` whose primitives share a state record (one draw): `(start, count)`.
fn draw_runs<'a>(list: &'a [u32], frame: &'a FrameData) -> impl Iterator<Item = (usize, usize)> + 'a {
    let mut start = 0;
    std::iter::from_fn(move || {
        let first = *list.get(start)?;
        let state = frame.primitives()[first as usize].state;
        let count = list[start..].iter().take_while(|&&e| frame.primitives()[e as usize].state == state).count();
        let run = (start, count);
        start += count;
        Some(run)
    })
}

/// Renders a tile's list in submission order (early-Z where the pipeline allows it).
pub fn render_in_order(
    list: &[u32],
    frame: &FrameData,
    draws: &[Draw],
    target: &mut RenderTarget,
    tally: &mut FragmentTally,
) {
    for (first, count) in draw_runs(list, frame) {
        let state = &frame.states()[frame.primitives()[list[first] as usize].state as usize];
        tally.draw = state.draw as usize;
        let run =
            PrimitiveRun::entries(frame.primitives(), frame.varyings(), &list[first..first + count], first as u32);
        draws[state.draw as usize].pipeline.object.rasterize(&run, target, tally, &mut Mode::InOrder);
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
    for (i, count) in draw_runs(list, frame) {
        let state = &frame.states()[frame.primitives()[list[i] as usize].state as usize];
        let pipeline = &draws[state.draw as usize].pipeline;
        let run = PrimitiveRun::entries(frame.primitives(), frame.varyings(), &list[i..i + count], i as u32);
        tally.draw = state.draw as usize;
        match state.hsr {
            HsrMode::Deferred { claims } => {
                if segment.is_none() {
                    visibility.reset(tile);
                    segment = Some(i);
                }
                let mut mode = Mode::Resolve { visibility, claims };
                pipeline.object.rasterize(&run, target, tally, &mut mode);
            }
            HsrMode::InOrder(reason) => {
                if let Some(start) = segment.take() {
                    shade_segment(list, start..i, frame, draws, target, tally, visibility);
                }
                tally.draw = state.draw as usize;
                let before = tally.counters.fragments_rasterized;
                pipeline.object.rasterize(&run, target, tally, &mut Mode::InOrder);
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
    let owners: Vec<u32> = visibility.owners_in(segment.start as u32, segment.len()).collect();
    let state_of = |position: u32| frame.primitives()[list[position as usize] as usize].state;
    let mut k = 0;
    while k < owners.len() {
        let first = owners[k];
        let mut count = 1;
        while k + count < owners.len()
            && owners[k + count] == first + count as u32
            && state_of(owners[k + count]) == state_of(first)
        {
            count += 1;
        }
        let state = &frame.states()[state_of(first) as usize];
        tally.draw = state.draw as usize;
        let entries = &list[first as usize..first as usize + count];
        let run = PrimitiveRun::entries(frame.primitives(), frame.varyings(), entries, first);
        let pipeline = &draws[state.draw as usize].pipeline;
        pipeline.object.rasterize(&run, target, tally, &mut Mode::Shade { visibility });
        k += count;
    }
    let shaded = tally.counters.fragments_shaded - shaded_before;
    tally.counters.fragments_hsr_killed += tally.hsr_candidates.saturating_sub(shaded);
    tally.hsr_candidates = 0;
}
