//! Reading and decoding a capture on a thread of its own, ahead of the replay.
//!
//! The replay's thread is the only one working between render passes (translating calls,
//! building textures); reading and decoding the capture there too made them wait for each
//! other. Here a reader thread decodes calls into a queue the replay takes them from, in
//! order. What it holds ahead is bounded: at most [`AHEAD_CALLS`] calls, and [`AHEAD_BYTES`]
//! of their values (a batch holding a larger call, which the reader's limits allow, goes alone).
//! The reader stops at its first error, which the replay meets after the calls before it; a
//! replay that stops first closes the queue, and the reader stops too.
//!
//! Calls go through the queue in batches of up to [`BATCH_CALLS`] calls or [`BATCH_BYTES`] of
//! values. Handed over one at a time, each call woke the other thread: a capture's thousands
//! of set-up calls (glmark2's are 2,300 before its first draw) took 2.6 µs each, the time of a
//! wake-up rather than of reading or translating one, and were a tenth of a short replay.

use std::sync::mpsc::{Receiver, SyncSender};
use std::sync::{Arc, Condvar, Mutex};

use tiler_apitrace::wire::FunctionSig;
use tiler_apitrace::{Decoder, GlesCall, TraceReader};

use super::CaptureError;

/// Calls read ahead, at most: glmark2's frames are a few hundred calls.
pub(super) const AHEAD_CALLS: usize = 4096;

/// Bytes of the values of the calls read ahead (texture and buffer uploads), at most.
pub(super) const AHEAD_BYTES: usize = 64 << 20;

/// Calls a batch holds, at most.
pub(super) const BATCH_CALLS: usize = 64;

/// Bytes of values after which a batch goes at once (an upload need not wait for the calls
/// after it).
pub(super) const BATCH_BYTES: usize = 256 << 10;

/// Batches the queue holds, at most: [`AHEAD_CALLS`] calls.
pub(super) const AHEAD_BATCHES: usize = AHEAD_CALLS / BATCH_CALLS;

/// A decoded call and its function's signature.
pub(super) type Decoded = (GlesCall, Arc<FunctionSig>);

/// A call as read: decoded, or the error that ended the reading.
type Item = Result<Decoded, CaptureError>;

/// What the reader sends: calls in order (the last may be an error) and the bytes of values
/// they hold against the budget.
pub(super) type Batch = (Vec<Item>, usize);

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

/// The reader thread: reads and decodes every call of `reader` into `sender` in batches, in
/// order, until the end, an error (sent last), or the replay stopping.
pub(super) fn read<R: std::io::Read>(reader: TraceReader<R>, sender: &SyncSender<Batch>, budget: &Budget) {
    let mut decoder = Decoder::new();
    let (mut batch, mut bytes) = (Vec::with_capacity(BATCH_CALLS), 0);
    for call in reader {
        let item: Item = call.map_err(CaptureError::from).and_then(|call| {
            bytes += call.held_bytes();
            let sig = call.sig.clone();
            Ok((decoder.decode(call)?, sig))
        });
        let failed = item.is_err();
        batch.push(item);
        if failed || batch.len() == BATCH_CALLS || bytes >= BATCH_BYTES {
            let full = std::mem::replace(&mut batch, Vec::with_capacity(BATCH_CALLS));
            if !send(sender, budget, (full, std::mem::take(&mut bytes))) || failed {
                return;
            }
        }
    }
    if !batch.is_empty() {
        send(sender, budget, (batch, bytes));
    }
}

/// Sends `batch` once its bytes fit the budget; `false` when the replay has stopped.
fn send(sender: &SyncSender<Batch>, budget: &Budget, batch: Batch) -> bool {
    budget.take(batch.1) && sender.send(batch).is_ok()
}

/// The replay's side of the queue: the calls in order, each batch released from the budget
/// as it is taken.
pub(super) struct Received<'a> {
    receiver: Receiver<Batch>,
    budget: &'a Budget,
    batch: std::vec::IntoIter<Item>,
}

impl<'a> Received<'a> {
    pub(super) fn new(receiver: Receiver<Batch>, budget: &'a Budget) -> Received<'a> {
        Received { receiver, budget, batch: Vec::new().into_iter() }
    }
}

impl Iterator for Received<'_> {
    type Item = Result<Decoded, CaptureError>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            if let Some(item) = self.batch.next() {
                return Some(item);
            }
            let (batch, bytes) = self.receiver.recv().ok()?;
            self.budget.release(bytes);
            self.batch = batch.into_iter();
        }
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
