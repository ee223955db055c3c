//! Reading and decoding a capture on a thread of its own, ahead of the replay.
//!
//! The replay's thread is the only one working between render passes (translating calls,
//! building textures); reading and decoding the capture there too made them wait for each
//! other. Here a reader thread decodes calls into a queue the replay takes them from, in
//! order. What it holds ahead is bounded: at most [`AHEAD_CALLS`] calls, and [`AHEAD_BYTES`]
//! of their values (a single larger call, which the reader's limits allow, goes alone).
//! The reader stops at its first error, which the replay meets after the calls before it; a
//! replay that stops first closes the queue, and the reader stops too.

use std::sync::mpsc::{Receiver, SyncSender};
use std::sync::{Arc, Condvar, Mutex};

use tiler_apitrace::wire::FunctionSig;
use tiler_apitrace::{Decoder, GlesCall, TraceReader};

use super::CaptureError;

/// Calls read ahead, at most: glmark2's frames are a few hundred calls.
pub(super) const AHEAD_CALLS: usize = 4096;

/// Bytes of the values of the calls read ahead (texture and buffer uploads), at most.
pub(super) const AHEAD_BYTES: usize = 64 << 20;

/// A decoded call and its function's signature.
pub(super) type Decoded = (GlesCall, Arc<FunctionSig>);

/// What the reader sends: a call and the bytes it holds against the budget, or the error
/// that ended the reading.
type Item = Result<(Decoded, usize), CaptureError>;

/// The bytes of values in the queue.
pub(super) struct Budget {
    limit: usize,
    /// Bytes held, and whether the replay has stopped taking calls.
    state: Mutex<(usize, bool)>,
    changed: Condvar,
}

impl Budget {
    pub(super) fn new(limit: usize) -> Budget {
        Budget { limit, state: Mutex::new((0, false)), changed: Condvar::new() }
    }

    /// Waits until `bytes` fit (or nothing is held); `false` when the replay has stopped.
    fn take(&self, bytes: usize) -> bool {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        while !state.1 && state.0 > 0 && state.0 + bytes > self.limit {
            state = self.changed.wait(state).unwrap_or_else(|e| e.into_inner());
        }
        state.0 += bytes;
        !state.1
    }

    fn release(&self, bytes: usize) {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        state.0 -= bytes;
        self.changed.notify_one();
    }

    fn close(&self) {
        self.state.lock().unwrap_or_else(|e| e.into_inner()).1 = true;
        self.changed.notify_one();
    }
}

/// Closes the budget when dropped: the replay has stopped taking calls.
pub(super) struct CloseOnDrop<'a>(pub(super) &'a Budget);

impl Drop for CloseOnDrop<'_> {
    fn drop(&mut self) {
        self.0.close();
    }
}

/// The reader thread: reads and decodes every call of `reader` into `sender`, in order,
/// until the end, an error (sent), or the replay stopping.
pub(super) fn read<R: std::io::Read>(reader: TraceReader<R>, sender: &SyncSender<Item>, budget: &Budget) {
    let mut decoder = Decoder::new();
    for call in reader {
        let item: Item = call.map_err(CaptureError::from).and_then(|call| {
            let (bytes, sig) = (call.held_bytes(), call.sig.clone());
            Ok(((decoder.decode(call)?, sig), bytes))
        });
        let failed = item.is_err();
        let bytes = item.as_ref().map_or(0, |(_, bytes)| *bytes);
        if !budget.take(bytes) || sender.send(item).is_err() || failed {
            return;
        }
    }
}

/// The replay's side of the queue: the calls in order, each released from the budget as it
/// is taken.
pub(super) struct Received<'a> {
    pub(super) receiver: Receiver<Item>,
    pub(super) budget: &'a Budget,
}

impl Iterator for Received<'_> {
    type Item = Result<Decoded, CaptureError>;

    fn next(&mut self) -> Option<Self::Item> {
        let item = self.receiver.recv().ok()?;
        Some(item.map(|(decoded, bytes)| {
            self.budget.release(bytes);
            decoded
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_budget_waits_for_room_and_lets_a_large_call_alone() {
        let budget = Budget::new(100);
        assert!(budget.take(60));
        std::thread::scope(|scope| {
            // 60 + 50 > 100: the second waits until the first is released.
            let waiting = scope.spawn(|| budget.take(50));
            std::thread::sleep(std::time::Duration::from_millis(20));
            assert!(!waiting.is_finished());
            budget.release(60);
            assert!(waiting.join().unwrap());
        });
        budget.release(50);
        // Larger than the whole budget, with nothing held: it goes.
        assert!(budget.take(500));
    }

    #[test]
    fn a_closed_budget_stops_a_waiting_reader() {
        let budget = Budget::new(100);
        assert!(budget.take(100));
        std::thread::scope(|scope| {
            let waiting = scope.spawn(|| budget.take(1));
            std::thread::sleep(std::time::Duration::from_millis(20));
            budget.close();
            assert!(!waiting.join().unwrap());
        });
    }
}
