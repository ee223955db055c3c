//! libFuzzer target: any bytes as a trace; parsing and replaying must fail cleanly, never
//! panic. Seed the corpus with the example traces: `cp ../traces/*.json corpus/trace/`.

#![no_main]

use libfuzzer_sys::fuzz_target;
use tiler_gl::{Limits, Trace};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let limits = Limits {
        max_data_bytes: 4 << 20,
        max_frames: 16,
        max_calls: 4096,
        memory_limit: Some(4 << 20),
        threads: Some(1),
    };
    if let Ok(trace) = Trace::parse_with(text, None, limits) {
        let _ = trace.replay_with(limits);
    }
});
