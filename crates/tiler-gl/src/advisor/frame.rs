//! The rules about a frame outside its passes: buffers and textures copied on write, stalls
//! waiting for the GPU, and stores nothing read.

use super::{Cost, Draft, PassIndex, RuleId, bytes, framebuffer_name};
use crate::report::{CallRef, FrameRecord, Role, Slot, StallCause, StoreKind};

/// Runs every frame rule over `frame`.
pub(super) fn check(frame: &FrameRecord, index: &PassIndex, out: &mut Vec<Draft>) {
    copy_on_write(frame, out);
    stalls(frame, out);
    store_unread(frame, index, out);
}

/// A finding about the frame, at a call outside any pass.
fn about_frame(rule: RuleId, frame: &FrameRecord, call: CallRef, cost: Cost, detail: String, fix: String) -> Draft {
    Draft { rule, frame: frame.index, pass: None, call: Some(call), cost, detail, fix }
}

/// Objects changed while a frame in flight used them: one finding per object per frame.
fn copy_on_write(frame: &FrameRecord, out: &mut Vec<Draft>) {
    let mut objects: Vec<&str> = frame.copies.iter().map(|c| c.object.as_str()).collect();
    objects.sort();
    objects.dedup();
    for object in objects {
        let copies: Vec<_> = frame.copies.iter().filter(|c| c.object == object).collect();
        let cost: u64 = copies.iter().map(|c| c.bytes).sum();
        out.push(about_frame(
            RuleId::CopyOnWrite,
            frame,
            copies[0].call,
            Cost { bytes: cost, ..Cost::default() },
            format!(
                "{object} was changed {} time(s) while a frame in flight (frame {}) still used it: the driver copied \
                 {} bytes ({} of traffic)",
                copies.len(),
                copies[0].used_in_frame,
                copies.iter().map(|c| c.bytes_copied).sum::<u64>(),
                bytes(cost)
            ),
            "make all updates before the draws that use it, replace it whole with buffer_data (orphaning), or rotate \
             as many copies as there are frames in flight"
                .to_string(),
        ));
    }
}

/// Waits for results still in the pipeline: `readback-stall`, `query-stall`, `finish-stall`,
/// by what waited.
fn stalls(frame: &FrameRecord, out: &mut Vec<Draft>) {
    for stall in &frame.stalls {
        let (rule, what, fix) = match stall.cause {
            StallCause::ReadPixels => (
                RuleId::ReadbackStall,
                "read_pixels",
                "read from a framebuffer rendered frames in flight earlier (rotate several framebuffers)",
            ),
            StallCause::QueryResult => (
                RuleId::QueryStall,
                "query_result",
                "poll query_available and read the result when it is true, frames in flight later",
            ),
            StallCause::Finish => (RuleId::FinishStall, "finish", "do not call finish; let the pipeline run"),
            StallCause::FenceWait => (
                RuleId::FinishStall,
                "client_wait_sync",
                "wait on a fence frames in flight old, or poll it with a zero timeout",
            ),
        };
        out.push(about_frame(
            rule,
            frame,
            stall.call,
            Cost { stall_frames: stall.frames, ..Cost::default() },
            format!(
                "{what} at {} waited for frame {}'s work: {} frame(s) of pipelining lost (results arrive {} frame(s) \
                 after submission)",
                stall.call, stall.waited_for_frame, stall.frames, frame.latency_frames
            ),
            fix.to_string(),
        ));
    }
}

/// Stores nothing read before they were overwritten or became undefined. The two halves of a
/// packed depth-stencil word move together (a store of either half writes the whole word):
/// both dead, they are one finding, invalidated together; one dead while the other is stored,
/// invalidating it would save nothing, so it is not reported.
fn store_unread(frame: &FrameRecord, index: &PassIndex, out: &mut Vec<Draft>) {
    for dead in &frame.dead_stores {
        let Some(pass) = index.numbered(dead.pass) else { continue };
        let Some(attachment) = pass.attachment(dead.slot) else { continue };
        if attachment.role == Role::Preserved {
            continue; // counted by packed-depth-stencil-half
        }
        let mut slots = dead.slot.to_string();
        let mut cost = dead.bytes;
        let half = match dead.slot {
            Slot::Depth => Some(Slot::Stencil),
            Slot::Stencil => Some(Slot::Depth),
            Slot::Color(_) => None,
        };
        if let Some(other) = half.filter(|_| attachment.format.has_depth() && attachment.format.has_stencil()) {
            let other_dead =
                frame.dead_stores.iter().find(|d| d.pass == dead.pass && d.image == dead.image && d.slot == other);
            match other_dead {
                // Reported once, with the depth half.
                Some(_) if dead.slot == Slot::Stencil => continue,
                Some(other_dead) => {
                    slots = "depth and stencil".to_string();
                    cost += other_dead.bytes;
                }
                None if pass.attachment(other).is_some_and(|a| a.store == StoreKind::Store) => continue,
                None => {}
            }
        }
        let fb = framebuffer_name(pass);
        let mut draft = Draft::about(
            RuleId::StoreUnread,
            pass,
            Some(pass.ended_at),
            Cost { bytes: cost, ..Cost::default() },
            format!(
                "pass {} stored the {slots} of {fb} ({}) and nothing read it before it was {}",
                pass.index,
                bytes(cost),
                dead.fate
            ),
            format!(
                "invalidate {slots} before unbinding {fb} (invalidate / glInvalidateFramebuffer), so it is never written out"
            ),
        );
        draft.frame = dead.frame;
        out.push(draft);
    }
}
